package reducerload.cordic

import chisel3._

/** Pipeline state: the vector, the residual angle, and the quadrant companion register. */
class CordicStateBundle(p: CordicParams, zWidth: Int) extends Bundle {
  val x = SInt(p.xyFormat.width.W)
  val y = SInt(p.xyFormat.width.W)
  val z = SInt(zWidth.W)
  val quadrant = UInt(2.W)
}

/** The vector and its quadrant, without the angle: what waits beside the residual rotation's multiplies. */
class CordicVectorBundle(p: CordicParams) extends Bundle {
  val x = SInt(p.xyFormat.width.W)
  val y = SInt(p.xyFormat.width.W)
  val quadrant = UInt(2.W)
}

/** cos and sin as raw codes of `p.outputFormat`. */
class SinCos(p: CordicParams) extends Bundle {
  val cos = SInt(p.outputFormat.width.W)
  val sin = SInt(p.outputFormat.width.W)
}
