package reducerload.fixedpoint

import chisel3._
import chisel3.util._

/** Hardware counterparts of the integer operations in [[FixedFormat]]; each has the same name there. */
object FixedHw {

  /**
   * `n` registers in a row, without reset, keeping `x`'s width (chisel3.util.ShiftRegister leaves the
   * width to inference, which elaboration-time width checks cannot read).
   */
  def delay[T <: Data](x: T, n: Int): T = {
    require(n >= 0, s"delay: cannot delay by $n cycles")
    (0 until n).foldLeft(x) { (v, _) =>
      val r = Reg(chiselTypeOf(x))
      r := v
      r
    }
  }

  /** Arithmetic right shift by `drop` bits with rounding; the result keeps the input width. */
  def shiftRound(x: SInt, drop: Int, rounding: Rounding): SInt = {
    require(drop >= 0, s"shiftRound: cannot drop $drop bits")
    if (drop == 0) x
    else
      rounding match {
        case Rounding.Truncate => x >> drop
        case Rounding.HalfUp =>
          // One extra bit so adding half an LSB cannot wrap; the shift removes it again.
          ((x +& (BigInt(1) << (drop - 1)).S) >> drop).asSInt
      }
  }

  /** Clamp `x` into `to`: (value in `to`'s width, out-of-range flag). */
  def saturate(x: SInt, to: FixedFormat): (SInt, Bool) = {
    if (x.getWidth <= to.width) (x.pad(to.width), false.B)
    else {
      val high = x > to.maxRaw.S
      val low = x < to.minRaw.S
      val clamped = Mux(high, to.maxRaw.S(to.width.W), Mux(low, to.minRaw.S(to.width.W), x(to.width - 1, 0).asSInt))
      (clamped, high || low)
    }
  }

  /**
   * `a + b` when `subtract` is low, `a - b` when high, in one carry chain: `a + (b ^ s) + s`.
   * The carry-in rides in an extra low bit (`{a,1} + {b^s,s}`) so synthesis sees one adder, not
   * an adder plus an incrementer or two adders and a mux. Result has `a`'s width (callers prove
   * the range).
   */
  def addSub(a: SInt, b: SInt, subtract: Bool): SInt = {
    val w = a.getWidth
    require(b.getWidth <= w, s"addSub: operand of ${b.getWidth} bits is wider than the accumulator's $w")
    val bExt = b.pad(w).asUInt ^ Fill(w, subtract)
    val sum = Cat(a.asUInt, 1.U(1.W)) + Cat(bExt, subtract)
    sum(w, 1).asSInt
  }
}
