// Estimator self-test: a registered 16-bit adder and a registered 18x18 signed multiply.
module est_probe(
  input              clock,
  input      [15:0]  a, b,
  input      [17:0]  x, y,
  output reg [15:0]  sum,
  output reg [35:0]  prod
);
  reg [17:0] xr, yr;
  always @(posedge clock) begin
    sum <= a + b;
    xr <= x;
    yr <= y;
    prod <= $signed(xr) * $signed(yr);
  end
endmodule
