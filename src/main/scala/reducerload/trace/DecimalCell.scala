package reducerload.trace

/**
 * The number in a CSV cell, read straight from the text: what [[TraceCsv.parseNumber]] returns for
 * the trimmed cell, without a substring, a regular expression or (usually) a call to
 * `java.lang.Double.parseDouble`. Blanks (space, tab) around the number are allowed, as the reader
 * trims them. Anything else (an empty cell, other characters, an infinite value) gives NaN, which
 * [[TraceCsv.parseNumber]] never returns: the caller then takes the general path, which explains
 * the problem in its error message.
 */
object DecimalCell {
  /** 10^0 .. 10^22: exactly representable doubles. */
  private val exactPowers: Array[Double] = Array.tabulate(23)(i => s"1e$i".toDouble)

  /** Mantissas up to 2^53 are exact doubles. */
  private val exactMantissa = 1L << 53

  /**
   * The number in `text(from until until)`, or NaN. Grammar (after blanks): `[+-]?` then digits with
   * at most one `.` and at least one digit, then optionally `e|E [+-]? digits` (TraceCsv's). The value
   * is correctly rounded, like `parseDouble`: with at most 2^53 as the mantissa and a power of ten up
   * to 10^22, one IEEE multiplication or division of two exact doubles rounds once (Clinger's fast
   * path); other numbers go to `parseDouble`.
   */
  def parse(text: CharSequence, from: Int, until: Int): Double = {
    var i = from
    var end = until
    while (i < end && isBlank(text.charAt(i))) i += 1
    while (end > i && isBlank(text.charAt(end - 1))) end -= 1
    val start = i
    val negative = i < end && text.charAt(i) == '-'
    if (i < end && (text.charAt(i) == '-' || text.charAt(i) == '+')) i += 1
    var mantissa = 0L
    var significant = 0 // digits after leading zeros, at most 18 (they fit a long)
    var digits = 0
    var fractionDigits = 0 // digits after the point that went into the mantissa or were zeros
    var dropped = false // a significant digit beyond the 18th: not exact
    var point = false
    var more = true
    while (more && i < end) {
      val c = text.charAt(i)
      if (c >= '0' && c <= '9') {
        digits += 1
        if (significant < 18) {
          if (significant > 0 || c != '0') { mantissa = mantissa * 10 + (c - '0'); significant += 1 }
          if (point) fractionDigits += 1
        } else dropped = true
        i += 1
      } else if (c == '.' && !point) { point = true; i += 1 }
      else more = false
    }
    if (digits == 0) return Double.NaN
    var exponent = 0
    if (i < end && (text.charAt(i) == 'e' || text.charAt(i) == 'E')) {
      i += 1
      val negativeExponent = i < end && text.charAt(i) == '-'
      if (i < end && (text.charAt(i) == '-' || text.charAt(i) == '+')) i += 1
      val exponentStart = i
      while (i < end && text.charAt(i) >= '0' && text.charAt(i) <= '9') {
        if (exponent < 100000) exponent = exponent * 10 + (text.charAt(i) - '0')
        i += 1
      }
      if (i == exponentStart) return Double.NaN
      if (negativeExponent) exponent = -exponent
    }
    if (i != end) return Double.NaN
    val power = exponent - fractionDigits
    val value =
      if (!dropped && mantissa <= exactMantissa && power >= -22 && power <= 22) {
        val m = mantissa.toDouble
        val v = if (power >= 0) m * exactPowers(power) else m / exactPowers(-power)
        if (negative) -v else v
      } else java.lang.Double.parseDouble(text.subSequence(start, end).toString)
    if (value.isInfinite) Double.NaN else value
  }

  private def isBlank(c: Char): Boolean = c == ' ' || c == '\t'
}
