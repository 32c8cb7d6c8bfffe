package reducerload.sim

import reducerload.fixedpoint.{FixedFormat, Rounding}

/**
 * [[FixedFormat]]'s conversions between doubles and codes, bit-identical, in double arithmetic where
 * that is exact: the reference goes through BigDecimal (tens of microseconds per value), which a
 * million-sample replay cannot afford. Anything near a rounding tie or too wide takes the reference.
 */
object FastFixed {
  /** |x·2^f| below this: a double's decimal rendering (what BigDecimal(x) takes) is within 2^-13 of it. */
  private val exactLimit = math.pow(2, 40)
  /** Fractions closer than this to a tie take the reference path, whose decimal rendering may fall either side. */
  private val tieMargin = math.pow(2, -10)

  /** `f.quantize(x, Rounding.HalfUp)`. */
  def quantizeHalfUp(x: Double, f: FixedFormat): BigInt = {
    val scaled = math.scalb(x, f.fracBits) // exact: a power-of-two scaling
    val floor = math.floor(scaled)
    val fraction = scaled - floor // exact for |scaled| < 2^52
    if (math.abs(scaled) < exactLimit && math.abs(fraction - 0.5) > tieMargin) BigInt(floor.toLong + (if (fraction > 0.5) 1 else 0))
    else f.quantize(x, Rounding.HalfUp)
  }

  /** `f.fromDouble(x, Rounding.HalfUp)._1`: round to nearest, saturate at the format. */
  def codeHalfUp(x: Double, f: FixedFormat): BigInt = FixedFormat.saturate(quantizeHalfUp(x, f), f)._1

  /** `FixedFormat.scaleDown(raw, fracBits)`: exact in doubles when the code has at most 53 bits. */
  def toDouble(raw: BigInt, fracBits: Int): Double =
    if (raw.bitLength <= 53) math.scalb(raw.toLong.toDouble, -fracBits) else FixedFormat.scaleDown(raw, fracBits)

  /** A binary angle code of `rad` (full turn = 2^bits, wraps), as the models' `angleCode` computes it. */
  def angleCode(rad: Double, bits: Int): BigInt = {
    require(!rad.isNaN && !rad.isInfinite, s"angle $rad is not a finite number")
    val turns = rad / (2 * math.Pi)
    quantizeHalfUp(turns - math.floor(turns), FixedFormat(62, bits)).mod(BigInt(1) << bits)
  }
}
