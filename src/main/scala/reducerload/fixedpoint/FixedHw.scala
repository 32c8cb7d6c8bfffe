package reducerload.fixedpoint

import chisel3._
import chisel3.util._

/** Hardware counterparts of the integer operations in [[FixedFormat]]; each has the same name there. */
object FixedHw {

  /**
   * `r`, a register, kept by synthesis (Verilog `keep` and `preserve`: Yosys and Quartus would merge
   * registers with the same input), so copies of one signal can each sit beside their own loads.
   */
  def kept[T <: Data](r: T): T = {
    dontTouch(r)
    chisel3.experimental.annotate(r)(Seq("keep", "preserve").map(firrtl.AttributeAnnotation(r.toTarget, _)))
    r
  }

  /**
   * `n` registers in a row, without reset, keeping `x`'s width (chisel3.util.ShiftRegister leaves the width
   * to inference, which elaboration-time width checks cannot read).
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
        case Rounding.HalfUp   =>
          // One extra bit so adding half an LSB cannot wrap; the shift removes it again.
          ((x +& (BigInt(1) << (drop - 1)).S) >> drop).asSInt
      }
  }

  /**
   * `v` in `width` bits where its range is proven to fit them: the top bits dropped only repeat the sign (the
   * analysis derived `width` from the value's range), or it is sign-extended.
   */
  def fitWidth(v: SInt, width: Int): SInt = if (v.getWidth >= width) v(width - 1, 0).asSInt else v.pad(width)

  /** Change the fraction bits by `drop`: fewer with `rounding` (drop > 0), more exactly (drop < 0). */
  def rescale(x: SInt, drop: Int, rounding: Rounding): SInt =
    if (drop >= 0) shiftRound(x, drop, rounding) else (x << -drop).asSInt

  /**
   * `x > c` for a constant `c`, as AND/OR logic instead of a subtractor: on offset binary (sign bit flipped,
   * so signed order is unsigned order), "x[i:0] > c[i:0]" is `x_i && below` where c_i = 1 and `x_i || below`
   * where c_i = 0. Synthesis packs the chain into about w/3 4-input LUTs, where a comparator on the carry
   * chain takes one LE per bit.
   */
  def greaterThan(x: SInt, c: BigInt): Bool = compareConst(x, c, greater = true)

  /**
   * `x < c` for a constant `c` (see [[greaterThan]]): "x[i:0] < c[i:0]" is `!x_i || below` where c_i = 1,
   * else `!x_i && below`.
   */
  def lessThan(x: SInt, c: BigInt): Bool = compareConst(x, c, greater = false)

  private def compareConst(x: SInt, c: BigInt, greater: Boolean): Bool = {
    val w = x.getWidth
    val (min, max) = (-(BigInt(1) << (w - 1)), (BigInt(1) << (w - 1)) - 1)
    if (greater && c >= max) false.B
    else if (greater && c < min) true.B
    else if (!greater && c <= min) false.B
    else if (!greater && c > max) true.B
    else {
      val offset = c - min // c in offset binary, 0 .. 2^w - 1
      val ux = x.asUInt ^ (BigInt(1) << (w - 1)).U(w.W)
      (0 until w).foldLeft(false.B) { (below, i) =>
        (greater, offset.testBit(i)) match {
          case (true, true)   => ux(i) && below
          case (true, false)  => ux(i) || below
          case (false, true)  => !ux(i) || below
          case (false, false) => !ux(i) && below
        }
      }
    }
  }

  /**
   * Clamp `x` to [min, max] (saturation, never wrap-around): (value in `width` bits, out-of-range flag).
   * `min` and `max` must fit `width` bits; in range, `x`'s low `width` bits are the value.
   */
  def clamp(x: SInt, min: BigInt, max: BigInt, width: Int): (SInt, Bool) =
    clampDecision(x, min, max, width).result

  /** [[clamp]] before its multiplexer (see [[Clamped]]). */
  def clampDecision(x: SInt, min: BigInt, max: BigInt, width: Int): Clamped = {
    val (lo, hi) = (-(BigInt(1) << (width - 1)), (BigInt(1) << (width - 1)) - 1)
    require(lo <= min && min <= max && max <= hi, s"clamp: [$min, $max] does not fit $width signed bits")
    val inRange = if (x.getWidth <= width) x.pad(width) else x(width - 1, 0).asSInt
    Clamped(inRange, greaterThan(x, max), lessThan(x, min), min, max)
  }

  /** Clamp `x` into `to`: (value in `to`'s width, out-of-range flag). */
  def saturate(x: SInt, to: FixedFormat): (SInt, Bool) = saturateDecision(x, to).result

  private def saturateDecision(x: SInt, to: FixedFormat): Clamped =
    if (x.getWidth <= to.width) Clamped(x.pad(to.width), false.B, false.B, to.minRaw, to.maxRaw)
    else clampDecision(x, to.minRaw, to.maxRaw, to.width)

  /**
   * `saturate(rescale(x, drop, HalfUp), to)`, with the saturation decided on `x` itself, beside the rounding
   * adder instead of after its carry chain: with d = drop > 0 and h = 2^(d-1), the rounded value floor((x +
   * h) / 2^d) is above `to.maxRaw` exactly when x > (maxRaw + 1) 2^d - h - 1 and below `to.minRaw` exactly
   * when x < minRaw 2^d - h. Only the final multiplexer follows the adder.
   */
  def roundSaturate(x: SInt, drop: Int, to: FixedFormat): (SInt, Bool) =
    roundSaturateDecision(x, drop, to).result

  /** [[roundSaturate]] before its final multiplexer (see [[Clamped]]). */
  def roundSaturateDecision(x: SInt, drop: Int, to: FixedFormat): Clamped = {
    val rounded = rescale(x, drop, Rounding.HalfUp)
    if (drop <= 0 || rounded.getWidth <= to.width)
      saturateDecision(rounded, to) // no rounding adder, or nothing to clamp
    else {
      val half = BigInt(1) << (drop - 1)
      val high = greaterThan(x, ((to.maxRaw + 1) << drop) - half - 1)
      val low = lessThan(x, (to.minRaw << drop) - half)
      Clamped(rounded(to.width - 1, 0).asSInt, high, low, to.minRaw, to.maxRaw)
    }
  }

  /**
   * `a + b` when `subtract` is low, `a - b` when high, in one carry chain: `a + (b ^ s) + s`. The carry-in
   * rides in an extra low bit (`{a,1} + {b^s,s}`) so synthesis sees one adder, not an adder plus an
   * incrementer or two adders and a mux. Result has `a`'s width (callers prove the range).
   */
  def addSub(a: SInt, b: SInt, subtract: Bool): SInt = {
    val w = a.getWidth
    require(b.getWidth <= w, s"addSub: operand of ${b.getWidth} bits is wider than the accumulator's $w")
    val bExt = b.pad(w).asUInt ^ Fill(w, subtract)
    val sum = Cat(a.asUInt, 1.U(1.W)) + Cat(bExt, subtract)
    sum(w, 1).asSInt
  }
}

/**
 * A value clamped to [min, max], before the multiplexer that picks a bound: `inRange` (the value's low bits,
 * right when neither compare holds) and whether it is above `max` or below `min`. Kept apart so a design can
 * register the compares and put the multiplexer in the next clock.
 */
final case class Clamped(inRange: SInt, high: Bool, low: Bool, min: BigInt, max: BigInt) {

  /** The clamped value, in `inRange`'s width. */
  def value: SInt = {
    val width = inRange.getWidth
    val v = Wire(SInt(width.W)) // a typed width, which delay and callers' width checks can read
    v := Mux(high, max.S(width.W), Mux(low, min.S(width.W), inRange))
    v
  }

  /** Out of range: the value saturated at a bound. */
  def outside: Bool = high || low

  /** (value, out-of-range flag). */
  def result: (SInt, Bool) = (value, outside)

  /** The decision in registers loaded when `enable` is high (no reset: data). */
  def registered(enable: Bool): Clamped =
    copy(inRange = RegEnable(inRange, enable), high = RegEnable(high, enable), low = RegEnable(low, enable))
}
