package reducerload.cordic

import chisel3._
import chisel3.util._

/**
 * Equation (10): fold a binary angle into its quadrant and a residual in [0, 90) degrees. The residual's top
 * `tableBits` bits pick a segment; z = residual - the segment's centre, and the start vector is the segment's
 * entry of `p.startTable`. Without a table this is the always-positive iteration 0: z = residual - 45
 * degrees, x = y = K cos 45. Combinational; with a table, the lookup is a case statement that synthesis maps
 * to ROM when its address and output are registered (CordicSinCos registers both).
 */
class QuadrantPreprocessor(p: CordicParams) extends Module {
  override def desiredName = s"QuadrantPreprocessor_${p.tag}"
  val io = IO(new Bundle {
    val angle = Input(UInt(p.angleBits.W))
    val state = Output(new CordicStateBundle(p, p.zFormat(p.firstIteration).width))
  })
  private val lowBits = p.residualBits - p.tableBits
  private val low = io.angle(lowBits - 1, 0)
  // low is in [0, segment) and the centre is its midpoint, so low - centre in two's complement is
  // low with its top bit inverted: no adder.
  private val z = Cat(~low(lowBits - 1), low(lowBits - 2, 0), 0.U(p.angleGuardBits.W)).asSInt
  io.state.quadrant := io.angle(p.angleBits - 1, p.angleBits - 2)
  io.state.z := z.pad(p.zFormat(p.firstIteration).width)
  private val w = p.xyFormat.width
  if (p.tableBits == 0) {
    io.state.x := p.startTable.head._1.S(w.W)
    io.state.y := p.startTable.head._2.S(w.W)
  } else {
    val segment = io.angle(p.residualBits - 1, lowBits)
    val table = VecInit(p.startTable.map { case (x, y) => Cat(x.S(w.W).asUInt, y.S(w.W).asUInt) })
    val entry = table(segment)
    io.state.x := entry(2 * w - 1, w).asSInt
    io.state.y := entry(w - 1, 0).asSInt
  }
}
