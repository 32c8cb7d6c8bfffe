package reducerload.sim

/**
 * The one text of a fixed-point code `code * 2^-fracBits` in a result file (the hardware's value
 * columns, `*_hw`), written by every path that writes result lines (harness engine, model engine,
 * the design's general `result`, and the tests' chiseltest path): the exact value as a plain decimal,
 * in integer arithmetic (no `Double.toString`). Rule:
 *  - a `-` before a negative value, nothing before a positive one or zero (a code has no signed zero);
 *  - the integer part's digits (at least one, so `0.5`), never an exponent;
 *  - then `.` and the fraction's digits up to its last non-zero one, which is exact: 2^-f has f
 *    decimals, so a code needs at most `fracBits` of them (`12.5`, `-0.00000095367431640625`);
 *  - an integer value is written with `.0` (`0.0`, `-3.0`, `12.0`), as `Double.toString` writes it,
 *    so the column always reads as decimals.
 * Codes of at most 63 bits with 0 to 59 fraction bits (every design's output port so far) take
 * long arithmetic; anything else takes BigDecimal, with the same rule (FixedDecimalSpec tests both
 * against BigDecimal).
 */
object FixedDecimal {
  /** The longest fraction the long path takes: `frac * 10` stays below 2^63. */
  private final val longFracBits = 59

  /** Append the text of `code * 2^-fracBits` to `text`. */
  def append(text: java.lang.StringBuilder, code: Long, fracBits: Int): java.lang.StringBuilder = {
    if (fracBits < 0 || fracBits > longFracBits || code == Long.MinValue) return appendExact(text, BigInt(code), fracBits)
    val magnitude = if (code < 0) { text.append('-'); -code } else code
    text.append(magnitude >>> fracBits)
    var fraction = magnitude & ((1L << fracBits) - 1)
    text.append('.')
    if (fraction == 0) text.append('0')
    else {
      // One decimal per step: the next digit is what ten times the fraction carries past the point.
      while (fraction != 0) {
        fraction *= 10
        text.append(('0' + (fraction >>> fracBits)).toChar)
        fraction &= (1L << fracBits) - 1
      }
    }
    text
  }

  /** [[append]] of a BigInt code (the design's general path): the long path when the code fits one. */
  def append(text: java.lang.StringBuilder, code: BigInt, fracBits: Int): java.lang.StringBuilder =
    if (code.isValidLong) append(text, code.toLong, fracBits) else appendExact(text, code, fracBits)

  /** The text of `code * 2^-fracBits` as a String. */
  def format(code: BigInt, fracBits: Int): String = append(new java.lang.StringBuilder, code, fracBits).toString

  /** The same rule in BigDecimal arithmetic (any code, any fracBits). */
  private[sim] def appendExact(text: java.lang.StringBuilder, code: BigInt, fracBits: Int): java.lang.StringBuilder = {
    val exact =
      if (fracBits >= 0) new java.math.BigDecimal(code.bigInteger.multiply(java.math.BigInteger.valueOf(5).pow(fracBits)), fracBits)
      else new java.math.BigDecimal(code.bigInteger.shiftLeft(-fracBits))
    val trimmed = exact.stripTrailingZeros
    val plain = (if (trimmed.scale < 0) trimmed.setScale(0) else trimmed).toPlainString
    text.append(plain)
    if (!plain.contains('.')) text.append(".0")
    text
  }
}
