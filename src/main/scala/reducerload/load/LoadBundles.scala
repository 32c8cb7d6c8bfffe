package reducerload.load

import chisel3._

/**
 * One sample: binary angles (full turn = 2^angleBits, any code is in range), velocities and
 * accelerations as raw codes of `p.velocityFormats` / `p.accelerationFormats`.
 */
class LoadInput(p: LoadParams) extends Bundle {
  val t1 = UInt(p.angleBits.W)
  val t2 = UInt(p.angleBits.W)
  val t3 = UInt(p.angleBits.W)
  val d1 = SInt(p.velocityFormats(0).width.W)
  val d2 = SInt(p.velocityFormats(1).width.W)
  val d3 = SInt(p.velocityFormats(2).width.W)
  val dd1 = SInt(p.accelerationFormats(0).width.W)
  val dd2 = SInt(p.accelerationFormats(1).width.W)
  val dd3 = SInt(p.accelerationFormats(2).width.W)
}

/** The load in N·m as a raw code of `p.outputFormat`, and whether an input was beyond its declared range. */
class LoadOutput(p: LoadParams) extends Bundle {
  val load = SInt(p.outputFormat.width.W)
  val outOfRange = Bool()
}
