package reducerload.trace

/**
 * The number in a CSV cell, read straight from the text: what [[TraceCsv.parseNumber]] returns for the
 * trimmed cell, without a substring, a regular expression or (usually) a call to
 * `java.lang.Double.parseDouble`. Blanks (space, tab) around the number are allowed, as the reader trims
 * them. Anything else (an empty cell, other characters, an infinite value) gives NaN, which
 * [[TraceCsv.parseNumber]] never returns: the caller then takes the general path, which explains the problem
 * in its error message.
 */
object DecimalCell {

  /** 10^0 .. 10^22: exactly representable doubles. */
  private val exactPowers: Array[Double] = Array.tabulate(23)(i => s"1e$i".toDouble)

  /** Mantissas up to 2^53 are exact doubles. */
  private val exactMantissa = 1L << 53

  /**
   * The number in `text(from until until)`, or NaN. Grammar (after blanks): `[+-]?` then digits with at most
   * one `.` and at least one digit, then optionally `e|E [+-]? digits` (TraceCsv's). The value is correctly
   * rounded, like `parseDouble`: with at most 2^53 as the mantissa and a power of ten up to 10^22, one IEEE
   * multiplication or division of two exact doubles rounds once (Clinger's fast path); other numbers of at
   * most 18 significant digits take the Eisel-Lemire algorithm (exact 128-bit products with a table of powers
   * of five); anything it cannot decide goes to `parseDouble`.
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
      } else {
        val bits = if (dropped) -1L else eiselLemire(mantissa, power)
        if (bits >= 0) { val v = java.lang.Double.longBitsToDouble(bits); if (negative) -v else v }
        else java.lang.Double.parseDouble(text.subSequence(start, end).toString)
      }
    if (value.isInfinite) Double.NaN else value
  }

  // ---- Eisel-Lemire (Lemire, "Number parsing at a gigabyte per second", 2021; as in fast_float) ----

  private val smallestPower = -342
  private val largestPower = 308

  /**
   * 5^q for q = -342..308 as 128-bit numbers with the top bit set (hi, lo interleaved): truncated for q >= 0,
   * floor(2^b / 5^-q) + 1 truncated to 128 bits for q < 0 (fast_float's table, computed here).
   */
  private val powersOfFive: Array[Long] = {
    val two128 = java.math.BigInteger.ONE.shiftLeft(128)
    val two127 = java.math.BigInteger.ONE.shiftLeft(127)
    (smallestPower to largestPower).toArray.flatMap { q =>
      val five = java.math.BigInteger.valueOf(5).pow(math.abs(q))
      val c =
        if (q >= 0) {
          val b = five.bitLength
          if (b <= 128) five.shiftLeft(128 - b) else five.shiftRight(b - 128)
        } else {
          val z = five.subtract(java.math.BigInteger.ONE).bitLength // least z with 2^z >= 5^-q
          val b = if (q >= -27) z + 127 else 2 * z + 128
          var r = java.math.BigInteger.ONE.shiftLeft(b).divide(five).add(java.math.BigInteger.ONE)
          while (r.compareTo(two128) >= 0) r = r.shiftRight(1)
          r
        }
      require(c.compareTo(two127) >= 0 && c.compareTo(two128) < 0, s"power of five $q")
      Array(c.shiftRight(64).longValue, c.longValue)
    }
  }

  private def unsignedMultiplyHigh(a: Long, b: Long): Long =
    Math.multiplyHigh(a, b) + ((a >> 63) & b) + ((b >> 63) & a)

  /**
   * The IEEE bits of the double nearest to `w * 10^q` (w exact, below 10^18, positive sign), or -1 when this
   * path cannot decide (subnormal, overflow, a product too close to call): the caller then asks parseDouble.
   */
  private def eiselLemire(w0: Long, q: Int): Long = {
    if (w0 == 0) return 0L
    if (q < smallestPower || q > largestPower) return -1L
    val lz = java.lang.Long.numberOfLeadingZeros(w0)
    val w = w0 << lz
    val index = 2 * (q - smallestPower)
    var low = w * powersOfFive(index)
    var high = unsignedMultiplyHigh(w, powersOfFive(index))
    if ((high & 0x1ffL) == 0x1ffL) {
      val secondHigh = unsignedMultiplyHigh(w, powersOfFive(index + 1))
      low += secondHigh
      if (java.lang.Long.compareUnsigned(secondHigh, low) > 0) high += 1
    }
    if (low == -1L && (q < -27 || q > 55)) return -1L
    val upper = (high >>> 63).toInt
    var mantissa = high >>> (upper + 9)
    var power2 = (((152170 + 65536) * q) >> 16) + 63 + upper - lz + 1023
    if (power2 <= 0) return -1L
    if (
      java.lang.Long.compareUnsigned(low, 1L) <= 0 && q >= -4 && q <= 23 && (mantissa & 3) == 1 &&
      (mantissa << (upper + 9)) == high
    ) mantissa &= ~1L
    mantissa += mantissa & 1
    mantissa >>>= 1
    if (mantissa >= (2L << 52)) { mantissa = 1L << 52; power2 += 1 }
    mantissa &= ~(1L << 52)
    if (power2 >= 0x7ff) return -1L
    mantissa | (power2.toLong << 52)
  }

  private def isBlank(c: Char): Boolean = c == ' ' || c == '\t'
}
