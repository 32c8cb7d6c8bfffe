// ECP5 mapping of the generator's registered signed multiply, used only by the Fmax proxy
// (estimate.py reads it over the design's own SignedMultiply with `read_verilog -overwrite`).
// Same behaviour as the generic module the generator emits: operand registers, then the product
// register, latency 2. Here the three registers are the MULT18X18D's own input and output
// registers, as Quartus packs the generic module's registers into a Cyclone IV embedded multiplier;
// Yosys does not pack fabric registers into ECP5 DSPs by itself.
module SignedMultiply #(
  parameter A_WIDTH = 18,
  parameter B_WIDTH = 18
) (
  input                                    clock,
  input      signed [A_WIDTH-1:0]         a,
  input      signed [B_WIDTH-1:0]         b,
  output     signed [A_WIDTH+B_WIDTH-1:0] product
);
  generate
    if (A_WIDTH <= 18 && B_WIDTH <= 18) begin : dsp
      // Sign-extend through unsigned wires: a `wire signed` here made Yosys 0.70's ABC9 step fail.
      wire [17:0] a18 = $signed(a);
      wire [17:0] b18 = $signed(b);
      wire [35:0] p;
      MULT18X18D #(
        .REG_INPUTA_CLK("CLK0"), .REG_INPUTB_CLK("CLK0"), .REG_OUTPUT_CLK("CLK0"), .GSR("DISABLED")
      ) mult (
        .A0(a18[0]), .A1(a18[1]), .A2(a18[2]), .A3(a18[3]), .A4(a18[4]), .A5(a18[5]), .A6(a18[6]), .A7(a18[7]), .A8(a18[8]),
        .A9(a18[9]), .A10(a18[10]), .A11(a18[11]), .A12(a18[12]), .A13(a18[13]), .A14(a18[14]), .A15(a18[15]), .A16(a18[16]), .A17(a18[17]),
        .B0(b18[0]), .B1(b18[1]), .B2(b18[2]), .B3(b18[3]), .B4(b18[4]), .B5(b18[5]), .B6(b18[6]), .B7(b18[7]), .B8(b18[8]),
        .B9(b18[9]), .B10(b18[10]), .B11(b18[11]), .B12(b18[12]), .B13(b18[13]), .B14(b18[14]), .B15(b18[15]), .B16(b18[16]), .B17(b18[17]),
        .SIGNEDA(1'b1), .SIGNEDB(1'b1), .SOURCEA(1'b0), .SOURCEB(1'b0), .CLK0(clock), .CE0(1'b1), .RST0(1'b0),
        .P0(p[0]), .P1(p[1]), .P2(p[2]), .P3(p[3]), .P4(p[4]), .P5(p[5]), .P6(p[6]), .P7(p[7]), .P8(p[8]), .P9(p[9]),
        .P10(p[10]), .P11(p[11]), .P12(p[12]), .P13(p[13]), .P14(p[14]), .P15(p[15]), .P16(p[16]), .P17(p[17]), .P18(p[18]),
        .P19(p[19]), .P20(p[20]), .P21(p[21]), .P22(p[22]), .P23(p[23]), .P24(p[24]), .P25(p[25]), .P26(p[26]), .P27(p[27]),
        .P28(p[28]), .P29(p[29]), .P30(p[30]), .P31(p[31]), .P32(p[32]), .P33(p[33]), .P34(p[34]), .P35(p[35])
      );
      assign product = p[A_WIDTH+B_WIDTH-1:0];
    end else begin : fabric
      reg signed [A_WIDTH-1:0] a_r;
      reg signed [B_WIDTH-1:0] b_r;
      reg signed [A_WIDTH+B_WIDTH-1:0] p_r;
      always @(posedge clock) begin
        a_r <= a;
        b_r <= b;
        p_r <= a_r * b_r;
      end
      assign product = p_r;
    end
  endgenerate
endmodule
