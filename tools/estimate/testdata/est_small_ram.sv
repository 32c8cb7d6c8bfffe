// A small memory with a registered read and no ram_style attribute, as firtool emits a memory-storage
// bank or a short delay: a Cyclone IV E has no LUT RAM, so the ECP5 proxy must build it in block RAM too.
module est_small_ram(
  input            clock,
  input      [3:0] waddr,
  input      [3:0] raddr,
  input            we,
  input      [7:0] in,
  output reg [7:0] out
);
  reg [7:0] mem [0:15];
  always @(posedge clock) begin
    if (we) mem[waddr] <= in;
    out <= mem[raddr];
  end
endmodule
