package reducerload.sim.text

/**
 * The one text of a fixed-point code `code * 2^-fracBits` in a result file (the hardware's value columns,
 * `*_hw`), written by every path that writes result lines (harness engine, model engine, the design's general
 * `result`, and the tests' chiseltest path): the exact value as a plain decimal, in integer arithmetic (no
 * `Double.toString`). Rule:
 *   - a `-` before a negative value, nothing before a positive one or zero (a code has no signed zero);
 *   - the integer part's digits (at least one, so `0.5`), never an exponent;
 *   - then `.` and the fraction's digits up to its last non-zero one, which is exact: 2^-f has f decimals, so
 *     a code needs at most `fracBits` of them (`12.5`, `-0.00000095367431640625`);
 *   - an integer value is written with `.0` (`0.0`, `-3.0`, `12.0`), as `Double.toString` writes it, so the
 *     column always reads as decimals.
 * Codes of at most 63 bits with 0 to 59 fraction bits (every design's output port so far) take long
 * arithmetic; anything else takes BigDecimal, with the same rule (FixedDecimalSpec tests both against
 * BigDecimal).
 */
object FixedDecimal {

  /**
   * The longest fraction the long path takes: `fraction * 10` stays below 2^63 (one digit a step at 59 bits).
   */
  private final val longFracBits = 59

  /** Append the text of `code * 2^-fracBits` to `text`. */
  def append(text: java.lang.StringBuilder, code: Long, fracBits: Int): java.lang.StringBuilder = {
    if (fracBits < 0 || fracBits > longFracBits || code == Long.MinValue)
      return appendExact(text, BigInt(code), fracBits)
    val magnitude = if (code < 0) { text.append('-'); -code }
    else code
    text.append(magnitude >>> fracBits)
    var fraction = magnitude & ((1L << fracBits) - 1)
    text.append('.')
    if (fraction == 0) text.append('0')
    else {
      // Several decimals per step: the next `step` digits are what 10^step times the fraction
      // carries past the point (10^step * 2^fracBits stays below 2^63); the last group's trailing
      // zeros are dropped.
      val step = digitsPerStep(fracBits)
      val scale = DoubleText.pow10(step)
      val mask = (1L << fracBits) - 1
      while (fraction != 0) {
        fraction *= scale
        var group = fraction >>> fracBits
        fraction &= mask
        val end = text.length + step
        text.setLength(end)
        var at = end
        while (at > end - step) { at -= 1; text.setCharAt(at, ('0' + group % 10).toChar); group /= 10 }
      }
      var last = text.length
      while (text.charAt(last - 1) == '0') last -= 1
      text.setLength(last)
    }
    text
  }

  /** Decimals per step for `fracBits`: the most k with 10^k < 2^(63 - fracBits) (one at 59 bits). */
  private val digitsPerStep: Array[Int] = Array.tabulate(longFracBits + 1)(f =>
    (1 to 18).filter(k => BigInt(10).pow(k) < (BigInt(1) << (63 - f))).max
  )

  /** [[append]] of a BigInt code (the design's general path): the long path when the code fits one. */
  def append(text: java.lang.StringBuilder, code: BigInt, fracBits: Int): java.lang.StringBuilder =
    if (code.isValidLong) append(text, code.toLong, fracBits) else appendExact(text, code, fracBits)

  /** The text of `code * 2^-fracBits` as a String. */
  def format(code: BigInt, fracBits: Int): String =
    append(new java.lang.StringBuilder, code, fracBits).toString

  /** The same rule in BigDecimal arithmetic (any code, any fracBits). */
  private[sim] def appendExact(
      text: java.lang.StringBuilder,
      code: BigInt,
      fracBits: Int
  ): java.lang.StringBuilder = {
    val exact =
      if (fracBits >= 0)
        new java.math.BigDecimal(
          code.bigInteger.multiply(java.math.BigInteger.valueOf(5).pow(fracBits)),
          fracBits
        )
      else new java.math.BigDecimal(code.bigInteger.shiftLeft(-fracBits))
    val trimmed = exact.stripTrailingZeros
    val plain = (if (trimmed.scale < 0) trimmed.setScale(0) else trimmed).toPlainString
    text.append(plain)
    if (!plain.contains('.')) text.append(".0")
    text
  }
}
