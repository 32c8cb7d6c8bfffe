package reducerload.fixedpoint

/** How a value loses fraction bits. Both are exact integer operations, mirrored bit for bit by hardware. */
sealed abstract class Rounding(val name: String) {
  override def toString: String = name
}
object Rounding {

  /** Floor (drop bits; two's complement truncation rounds toward minus infinity). Error in (-lsb, 0]. */
  case object Truncate extends Rounding("truncate")

  /** Round half up: add half an LSB, then floor. Error in (-lsb/2, lsb/2]. */
  case object HalfUp extends Rounding("half-up")

  val all: Seq[Rounding] = Seq(Truncate, HalfUp)
  def parse(s: String): Option[Rounding] = all.find(_.name == s)

  /** Worst-case magnitude of the error of one rounding step, in units of the kept LSB. */
  def maxErrorLsb(r: Rounding): Double = r match {
    case Truncate => 1.0
    case HalfUp   => 0.5
  }
}

/**
 * Overflow is never silent: formats are derived from proven ranges (the bit-accurate models check every value
 * against its format), and inputs beyond their declared ranges saturate and raise a flag
 * ([[FixedFormat.clamp]], [[FixedHw.clamp]]). There is no wrap-around mode.
 *
 * Signed two's complement fixed-point format: one sign bit, `intBits` integer bits and `fracBits` fraction
 * bits. A raw integer `r` stands for `r * 2^-fracBits`.
 */
final case class FixedFormat(intBits: Int, fracBits: Int) {
  require(fracBits >= 0, s"FixedFormat: fracBits must be >= 0, got $fracBits")
  // Negative intBits describe small values whose top bits would only repeat the sign: is 9 bits.
  require(1 + intBits + fracBits >= 2, s"FixedFormat: Q$intBits.$fracBits leaves fewer than 2 bits")
  require(
    intBits + fracBits <= 120,
    s"FixedFormat: ${1 + intBits + fracBits} bits is beyond any sane datapath"
  )

  /** Total width including the sign bit. */
  val width: Int = 1 + intBits + fracBits
  val lsb: Double = math.pow(2.0, -fracBits)
  val maxRaw: BigInt = (BigInt(1) << (width - 1)) - 1
  val minRaw: BigInt = -(BigInt(1) << (width - 1))
  def maxValue: Double = toDouble(maxRaw)
  def minValue: Double = toDouble(minRaw)

  def toDouble(raw: BigInt): Double = FixedFormat.scaleDown(raw, fracBits)
  def contains(raw: BigInt): Boolean = raw >= minRaw && raw <= maxRaw
  def fits(x: Double): Boolean = x >= minValue && x <= maxValue

  /** Nearest-below or nearest raw code of `x` (no range check). `x` must be finite. */
  def quantize(x: Double, rounding: Rounding): BigInt = {
    require(!x.isNaN && !x.isInfinite, s"FixedFormat.quantize: $x is not a finite number")
    val scaled = BigDecimal(x) * BigDecimal(2).pow(fracBits)
    val floor = scaled.setScale(0, BigDecimal.RoundingMode.FLOOR).toBigInt
    rounding match {
      case Rounding.Truncate => floor
      case Rounding.HalfUp =>
        (scaled + BigDecimal(0.5)).setScale(0, BigDecimal.RoundingMode.FLOOR).toBigInt
    }
  }

  /** Quantize and saturate: (raw code, saturated?). */
  def fromDouble(x: Double, rounding: Rounding): (BigInt, Boolean) =
    FixedFormat.saturate(quantize(x, rounding), this)

  override def toString: String = s"Q$intBits.$fracBits"

  /** Human-readable description for reports. */
  def describe: String =
    f"$toString (signed, $width bits, lsb 2^-$fracBits, range [$minValue%.10g, $maxValue%.10g])"
}

object FixedFormat {

  /** Bits needed so that every |value| <= maxAbs fits with `fracBits` fraction bits. */
  def forRange(maxAbs: Double, fracBits: Int): FixedFormat = {
    require(
      !maxAbs.isNaN && !maxAbs.isInfinite && maxAbs >= 0,
      s"FixedFormat.forRange: range $maxAbs is not a finite magnitude"
    )
    val needed = LazyList.from(0).find(i => math.pow(2.0, i) - math.pow(2.0, -fracBits) >= maxAbs).get
    FixedFormat(needed, fracBits)
  }

  /** Narrowest format with `fracBits` fraction bits holding every raw code in [-maxAbsRaw, maxAbsRaw]. */
  def forRawRange(maxAbsRaw: BigInt, fracBits: Int): FixedFormat = {
    require(maxAbsRaw >= 0, s"FixedFormat.forRawRange: negative magnitude $maxAbsRaw")
    FixedFormat((maxAbsRaw.bitLength + 1).max(2) - 1 - fracBits, fracBits)
  }

  def scaleDown(raw: BigInt, fracBits: Int): Double =
    (BigDecimal(raw) / BigDecimal(2).pow(fracBits)).toDouble

  /**
   * Arithmetic shift right by `drop` bits with the given rounding; the integer model of FixedHw.shiftRound.
   */
  def shiftRound(raw: BigInt, drop: Int, rounding: Rounding): BigInt = {
    require(drop >= 0, s"shiftRound: cannot drop $drop bits")
    if (drop == 0) raw
    else
      rounding match {
        case Rounding.Truncate => raw >> drop
        case Rounding.HalfUp   => (raw + (BigInt(1) << (drop - 1))) >> drop
      }
  }

  /**
   * Change the fraction bits by `drop`: fewer with `rounding` (drop > 0), more exactly (drop < 0). Model of
   * FixedHw.rescale.
   */
  def rescale(raw: BigInt, drop: Int, rounding: Rounding): BigInt =
    if (drop >= 0) shiftRound(raw, drop, rounding) else raw << -drop

  /**
   * Clamp to [min, max]: (clamped raw, was it out of range?). Saturation, never wrap-around. Model of
   * FixedHw.clamp.
   */
  def clamp(raw: BigInt, min: BigInt, max: BigInt): (BigInt, Boolean) =
    if (raw > max) (max, true)
    else if (raw < min) (min, true)
    else (raw, false)

  /**
   * The signed value of a `width`-bit two's-complement code given as its unsigned bits (0 <= raw < 2^width).
   */
  def fromTwosComplement(raw: BigInt, width: Int): BigInt =
    if (raw.testBit(width - 1)) raw - (BigInt(1) << width) else raw

  /** Clamp to the format: (clamped raw, was it out of range?). Model of FixedHw.saturate. */
  def saturate(raw: BigInt, to: FixedFormat): (BigInt, Boolean) = clamp(raw, to.minRaw, to.maxRaw)
}
