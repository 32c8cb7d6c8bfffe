package reducerload.cordic

import chisel3._
import chisel3.util._
import reducerload.fixedpoint.FixedHw

/**
 * The multiply-based end of the residual architecture, three registered steps:
 * 1. zr = z * 2pi (one 18x18 multiplier; z in turns -> radians on the x/y scale, truncated);
 * 2. x zr and y zr with x, y truncated to the bits that matter against |zr| (one 18x18 each);
 * 3. x' = x - y zr, y' = y + x zr (first order; its gain and angle error are in the error bound).
 * Registers sit on both sides of every multiplier; the quadrant and valid bit ride along.
 */
class ResidualRotation(p: CordicParams) extends Module {
  require(p.residual, "ResidualRotation: CordicParams.architecture must be residual")
  override def desiredName = s"ResidualRotation_${p.tag}"
  private val zWidth = p.zFormat(p.iterations).width
  val io = IO(new Bundle {
    val in = Input(Valid(new CordicStateBundle(p, zWidth)))
    val out = Output(Valid(new CordicStateBundle(p, zWidth)))
  })
  private val f = p.xyFormat.fracBits
  private val drop = f - p.residualOperandFracBits

  // Step 1: z to radians.
  private val zrFull = FixedHw.delay(io.in.bits.z * p.twoPiRaw.S((p.twoPiRaw.bitLength + 1).W), 1)
  private val zr = (zrFull >> (p.zFracBits + p.twoPiFracBits - f))(p.zrFormat.width - 1, 0).asSInt
  private val x1 = FixedHw.delay(io.in.bits.x, 1)
  private val y1 = FixedHw.delay(io.in.bits.y, 1)

  // Step 2: the two products (operands are register outputs, products are registered).
  private val xTrunc = (x1 >> drop).asSInt
  private val yTrunc = (y1 >> drop).asSInt
  private val xzr = FixedHw.delay(xTrunc * zr, 1)
  private val yzr = FixedHw.delay(yTrunc * zr, 1)
  private val x2 = FixedHw.delay(x1, 1)
  private val y2 = FixedHw.delay(y1, 1)

  // Step 3: rotate.
  private val w = p.xyFormat.width
  private val out = Reg(new CordicStateBundle(p, zWidth))
  out.x := (x2 - (yzr >> p.residualOperandFracBits).asSInt)(w - 1, 0).asSInt
  out.y := (y2 + (xzr >> p.residualOperandFracBits).asSInt)(w - 1, 0).asSInt
  out.z := 0.S
  out.quadrant := FixedHw.delay(io.in.bits.quadrant, 2)
  io.out.bits := out
  io.out.valid := ShiftRegister(io.in.valid, p.residualLatency, false.B, true.B)
}
