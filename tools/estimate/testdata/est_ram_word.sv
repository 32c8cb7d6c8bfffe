// A memory read as Chisel's SyncReadMem reads it (the address registered, then the word) into the RAM's
// output register and one more register in the logic, which an adder reads: an M9K holds the address and
// the output registers, the third takes a logic element of its own for each of its 8 bits.
module est_ram_word(
  input            clock,
  input      [4:0] address,
  input      [4:0] write,
  input      [7:0] in,
  input      [7:0] other,
  output reg [8:0] out
);
  (* ram_style = "block", no_rw_check *) reg [7:0] buffer [0:31];
  reg  [4:0] read;
  reg  [7:0] word;
  reg  [7:0] fabric;
  always @(posedge clock) begin
    buffer[write] <= in;
    read <= address;
    word <= buffer[read];
    fabric <= word;
    out <= fabric + other;
  end
endmodule
