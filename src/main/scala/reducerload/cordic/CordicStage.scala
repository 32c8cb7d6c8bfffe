package reducerload.cordic

import chisel3._
import chisel3.util._
import reducerload.fixedpoint.FixedHw

/**
 * Equation (8), registered: the micro-rotations `iterations` (consecutive i) followed by one pipeline
 * register. The quadrant and valid bit ride along in companion registers, so a new angle enters every clock.
 * Data registers have no reset: they are only read when valid is high, and valid resets to low.
 */
class CordicStage(p: CordicParams, iterations: Seq[Int]) extends Module {
  require(
    iterations.nonEmpty && iterations.head >= 1 && iterations.last < p.iterations,
    s"CordicStage: iterations $iterations outside 1..${p.iterations - 1}"
  )
  private val first = iterations.head
  private val last = iterations.last
  override def desiredName = s"CordicStage_${p.tag}_i$first" + (if (last != first) s"to$last" else "")

  val io = IO(new Bundle {
    val in = Input(Valid(new CordicStateBundle(p, p.zFormat(first).width)))
    val out = Output(Valid(new CordicStateBundle(p, p.zFormat(last + 1).width)))
  })

  /** One micro-rotation; z is narrowed to the proven range of the next iteration. */
  private def rotate(x: SInt, y: SInt, z: SInt, i: Int): (SInt, SInt, SInt) = {
    val negative = z(z.getWidth - 1) // s = -1: rotate clockwise
    val xNext = FixedHw.addSub(x, y >> i, subtract = !negative)
    val yNext = FixedHw.addSub(y, x >> i, subtract = negative)
    val zNext =
      if (i == p.iterations - 1 && !p.residual)
        0.S(p.zFormat(i + 1).width.W) // the last residual is never read
      else {
        val zFull = FixedHw.addSub(z, p.atanTable(i).S(z.getWidth.W), subtract = !negative)
        zFull(p.zFormat(i + 1).width - 1, 0).asSInt
      }
    (xNext, yNext, zNext)
  }

  private val (x, y, z) = iterations.foldLeft((io.in.bits.x, io.in.bits.y, io.in.bits.z)) {
    case ((x, y, z), i) =>
      rotate(x, y, z, i)
  }

  private val valid = RegNext(io.in.valid, false.B)
  private val bits = Reg(new CordicStateBundle(p, p.zFormat(last + 1).width))
  bits.x := x
  bits.y := y
  bits.z := z
  bits.quadrant := io.in.bits.quadrant
  io.out.valid := valid
  io.out.bits := bits
}
