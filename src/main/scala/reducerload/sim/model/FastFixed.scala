package reducerload.sim.model

import reducerload.fixedpoint.{FixedFormat, Rounding}

/**
 * [[FixedFormat]]'s conversions between doubles and codes, bit-identical, in double and long arithmetic where
 * that is exact: the reference goes through BigDecimal (tens of microseconds per value), which a
 * million-sample replay cannot afford. Anything near a rounding tie or too wide takes the reference.
 */
object FastFixed {

  /**
   * \|x·2^f| below this: a double's decimal rendering (what BigDecimal(x) takes; it reads back as x, so it is
   * within half an ulp of x) is within 2^-14 of it once scaled (an ulp below 2^40 is at most 2^-13).
   */
  private final val exactLimit = 1099511627776.0 // 2^40
  /**
   * Fractions closer than this to a tie take the reference path, whose decimal rendering may fall either
   * side; four times the rendering's distance, and small, so the slow BigDecimal path stays rare.
   */
  private final val tieMargin = 1.0 / 4096 // 2^-12
  /** "No fast answer": never a result of the fast path, whose results are below 2^41 in magnitude. */
  private final val noFastAnswer = Long.MinValue

  private def fastHalfUp(x: Double, fracBits: Int): Long = {
    val scaled = math.scalb(x, fracBits) // exact: a power-of-two scaling
    val floor = math.floor(scaled)
    val fraction = scaled - floor // exact for |scaled| < 2^52
    if (math.abs(scaled) < exactLimit && math.abs(fraction - 0.5) > tieMargin)
      floor.toLong + (if (fraction > 0.5) 1 else 0)
    else noFastAnswer
  }

  /** `f.quantize(x, Rounding.HalfUp)`. */
  def quantizeHalfUp(x: Double, f: FixedFormat): BigInt = {
    val v = fastHalfUp(x, f.fracBits)
    if (v != noFastAnswer) BigInt(v) else f.quantize(x, Rounding.HalfUp)
  }

  /** `f.fromDouble(x, Rounding.HalfUp)._1`: round to nearest, saturate at the format. */
  def codeHalfUp(x: Double, f: FixedFormat): BigInt = {
    val v = fastHalfUp(x, f.fracBits)
    if (v != noFastAnswer && f.width <= 63) BigInt(v.max(f.minRaw.toLong).min(f.maxRaw.toLong))
    else FixedFormat.saturate(quantizeHalfUp(x, f), f)._1
  }

  /**
   * [[codeHalfUp]] as a long, for a format of at most 63 bits whose limits are `min` and `max` ([[minOf]],
   * [[maxOf]]).
   */
  def codeHalfUpLong(x: Double, f: FixedFormat, min: Long, max: Long): Long = {
    val v = fastHalfUp(x, f.fracBits)
    if (v != noFastAnswer) (if (v < min) min else if (v > max) max else v)
    else FixedFormat.saturate(quantizeHalfUp(x, f), f)._1.toLong
  }

  /** `FixedFormat.scaleDown(raw, fracBits)`: exact in doubles when the code has at most 53 bits. */
  def toDouble(raw: BigInt, fracBits: Int): Double =
    if (raw.bitLength <= 53) math.scalb(raw.toLong.toDouble, -fracBits)
    else FixedFormat.scaleDown(raw, fracBits)

  /**
   * The format the models quantize a fraction of a turn in (`FixedFormat(62, bits)`), built once per design.
   */
  def angleFormat(bits: Int): FixedFormat = {
    require(bits >= 1 && bits <= 62, s"FastFixed: angle codes of $bits bits are not supported (1 to 62)")
    FixedFormat(62, bits)
  }

  /**
   * A binary angle code of `rad` (full turn = 2^bits, wraps), as the models' `angleCode` computes it; `f` is
   * [[angleFormat]].
   */
  def angleCode(rad: Double, f: FixedFormat): BigInt = {
    require(!rad.isNaN && !rad.isInfinite, s"angle $rad is not a finite number")
    val turns = rad / (2 * math.Pi)
    val fraction = turns - math.floor(turns)
    val v = fastHalfUp(fraction, f.fracBits)
    // Two's complement: the low bits are the non-negative residue modulo the turn.
    if (v != noFastAnswer) BigInt(v & ((1L << f.fracBits) - 1))
    else f.quantize(fraction, Rounding.HalfUp).mod(BigInt(1) << f.fracBits)
  }

  /** [[angleCode]] as a long. */
  def angleCodeLong(rad: Double, f: FixedFormat): Long = {
    require(!rad.isNaN && !rad.isInfinite, s"angle $rad is not a finite number")
    val turns = rad / (2 * math.Pi)
    val fraction = turns - math.floor(turns)
    val v = fastHalfUp(fraction, f.fracBits)
    if (v != noFastAnswer) v & ((1L << f.fracBits) - 1)
    else f.quantize(fraction, Rounding.HalfUp).mod(BigInt(1) << f.fracBits).toLong
  }

  /** [[toDouble]] of a long code. */
  def longToDouble(raw: Long, fracBits: Int): Double =
    if (raw >= -(1L << 53) && raw < (1L << 53)) math.scalb(raw.toDouble, -fracBits)
    else FixedFormat.scaleDown(BigInt(raw), fracBits)

  // ---- long arithmetic of the models (FastLoadModel), for formats of at most 62 bits ----

  /**
   * The least and greatest raw code of `f` as longs (`f.minRaw`, `f.maxRaw`); `f` is at most 63 bits wide.
   */
  def minOf(f: FixedFormat): Long = {
    require(f.width <= 63, s"FastFixed: $f is wider than 63 bits"); -(1L << (f.width - 1))
  }
  def maxOf(f: FixedFormat): Long = {
    require(f.width <= 63, s"FastFixed: $f is wider than 63 bits"); (1L << (f.width - 1)) - 1
  }

  /** `FixedFormat.shiftRound` of a long. */
  def shiftRound(raw: Long, drop: Int, rounding: Rounding): Long = {
    require(drop >= 0 && drop < 63, s"shiftRound: cannot drop $drop bits of a long")
    if (drop == 0) raw
    else
      rounding match {
        case Rounding.Truncate => raw >> drop
        case Rounding.HalfUp   => Math.addExact(raw, 1L << (drop - 1)) >> drop
      }
  }

  /**
   * `FixedFormat.shiftRound(a * b, drop, rounding)` on the exact 128-bit product; the result must fit a long
   * (otherwise an ArithmeticException, never a wrapped value).
   */
  def mulShiftRound(a: Long, b: Long, drop: Int, rounding: Rounding): Long = {
    require(drop >= 0 && drop < 127, s"mulShiftRound: cannot drop $drop bits")
    var lo = a * b
    var hi = Math.multiplyHigh(a, b)
    if (rounding == Rounding.HalfUp && drop > 0) {
      if (drop - 1 < 64) {
        val sum = lo + (1L << (drop - 1))
        if (java.lang.Long.compareUnsigned(sum, lo) < 0) hi += 1
        lo = sum
      } else hi += 1L << (drop - 1 - 64)
    }
    var result = lo
    var rest = hi
    if (drop >= 64) { result = hi >> (drop - 64); rest = hi >> 63 }
    else if (drop > 0) { result = (lo >>> drop) | (hi << (64 - drop)); rest = hi >> drop }
    if (rest != (result >> 63))
      throw new ArithmeticException(s"mulShiftRound: $a * $b >> $drop does not fit a long")
    result
  }
}
