// A block-RAM delay as pipeline/MemoryDelay.scala builds it (a circular buffer, the read address
// registered, the word read into an output register), its word read by an adder. The read never
// meets the write (firtool's memories read 'x' then, so Yosys adds no collision logic: no_rw_check).
module est_delay(
  input            clock,
  input            reset,
  input      [7:0] in,
  input      [7:0] other,
  output reg [8:0] out
);
  (* ram_style = "block", no_rw_check *) reg [7:0] buffer [0:30];
  reg  [4:0] write;
  reg  [4:0] read;
  reg  [7:0] word;
  wire [4:0] next = write == 5'd30 ? 5'd0 : write + 5'd1;
  always @(posedge clock) begin
    write <= reset ? 5'd0 : next;
    buffer[write] <= in;
    read <= next;
    word <= buffer[read];
    out <= word + other;
  end
endmodule
