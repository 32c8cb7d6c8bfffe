package reducerload.cordic

import chisel3._
import chisel3.util._

/**
 * Equation (10): fold a binary angle into its quadrant and a residual in [0, 90) degrees, then
 * apply the always-positive iteration 0: z1 = residual - 45 degrees, x1 = y1 = K. Combinational.
 */
class QuadrantPreprocessor(p: CordicParams) extends Module {
  override def desiredName = s"QuadrantPreprocessor_${p.tag}"
  val io = IO(new Bundle {
    val angle = Input(UInt(p.angleBits.W))
    val state = Output(new CordicStateBundle(p, p.zFormat(1).width))
  })
  val residual = io.angle(p.residualBits - 1, 0)
  // residual is in [0, 90) degrees and 45 degrees is its midpoint, so residual - 45 degrees in two's
  // complement is the residual with its top bit inverted: no adder.
  val z1 = Cat(~residual(p.residualBits - 1), residual(p.residualBits - 2, 0), 0.U(p.angleGuardBits.W)).asSInt
  io.state.quadrant := io.angle(p.angleBits - 1, p.angleBits - 2)
  io.state.z := z1.pad(p.zFormat(1).width)
  io.state.x := p.startRaw.S(p.xyFormat.width.W)
  io.state.y := p.startRaw.S(p.xyFormat.width.W)
}
