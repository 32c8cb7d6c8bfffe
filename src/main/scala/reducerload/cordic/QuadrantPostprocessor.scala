package reducerload.cordic

import chisel3._
import chisel3.util._
import reducerload.fixedpoint.Rounding

/**
 * Equation (11) plus output rounding, registered. By quadrant: 00 -> (cos, sin) = (x, y); 01 -> (-y, x); 10
 * -> (-x, -y); 11 -> (y, -x). Negation `~v + 1` and half-up rounding share one adder per output: round(-v) =
 * (~v + (1 + h)) >> g, round(v) = (v + h) >> g, with h half the output LSB (the model's
 * FixedFormat.shiftRound of +-v).
 */
class QuadrantPostprocessor(p: CordicParams) extends Module {
  override def desiredName = s"QuadrantPostprocessor_${p.tag}"
  val io = IO(new Bundle {
    val in = Input(Valid(new CordicStateBundle(p, p.zFormat(p.iterations).width)))
    val out = Output(Valid(new SinCos(p)))
  })

  private val g = p.guardBits
  private val half: BigInt = p.outputRounding match {
    case Rounding.HalfUp if g > 0 => BigInt(1) << (g - 1)
    case _                        => BigInt(0)
  }

  /** Round `v` or `-v` to the output format in one carry chain (range: |v| <= 1 + error, proven). */
  private def negateRound(v: SInt, negate: Bool): SInt = {
    val w = p.xyFormat.width
    val operand = (v.asUInt ^ Fill(w, negate)).asSInt
    val addend = Mux(negate, (half + 1).S((w + 1).W), half.S((w + 1).W))
    val sum = (operand +& addend)(w - 1, 0).asSInt // one bit dropped: |result| < 2 proven
    sum >> g
  }

  private val q = io.in.bits.quadrant
  private val swap = q(0) // quadrants 01 and 11 exchange x and y
  private val cosSource = Mux(swap, io.in.bits.y, io.in.bits.x)
  private val sinSource = Mux(swap, io.in.bits.x, io.in.bits.y)
  private val negateCos = q === 1.U || q === 2.U
  private val negateSin = q(1)

  private val out = Reg(new SinCos(p))
  out.cos := negateRound(cosSource, negateCos)
  out.sin := negateRound(sinSource, negateSin)
  io.out.valid := RegNext(io.in.valid, false.B)
  io.out.bits := out
}
