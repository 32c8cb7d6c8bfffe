// Estimator self-test: two kept copies of one register (`keep, preserve` on a reg) stay two
// registers, as Quartus keeps them: 3 x 4 register bits, each in an LE of its own.
module est_keep(
  input             clock,
  input      [3:0]  a,
  output     [7:0]  y
);
  reg [3:0] r;
  (* keep, preserve *) reg [3:0] c0;
  (* keep, preserve *) reg [3:0] c1;
  always @(posedge clock) begin
    r <= a;
    c0 <= r;
    c1 <= r;
  end
  assign y = {c1, c0};
endmodule
