package reducerload.sim.text

import java.lang.Math.multiplyHigh
import java.math.BigInteger

/**
 * The one text of a double in a result file (the reference and error columns, `*_ref` and `*_error`), written
 * by every path that writes result lines. Rule (JDK 19's `Double.toString`):
 *   - the digits: the shortest decimal that reads back as the same double; among those of that length, the
 *     nearest to it, ties to an even last digit;
 *   - the layout of `Double.toString`: plain for 10^-3 <= |x| < 10^7 (`-16.946797119039708`, `0.0012`,
 *     `30.0`), otherwise one digit, the point and an exponent (`-4.066568202176768E-6`, `1.0E7`); always a
 *     digit after the point; `0.0` and `-0.0`.
 * Subnormal doubles (below 2.2e-308), infinities and NaN are written by `Double.toString`.
 *
 * Why not `Double.toString` itself: on the JDK 17 this project runs on, it falls back to big-integer
 * arithmetic for many doubles (a replay writes two numbers per torque), and for some doubles it writes more
 * digits than needed or digits that are not the nearest (JDK-4511638, fixed in JDK 19 by the algorithm
 * below), where this rule writes the shortest nearest. This appends to the line's builder, with no String per
 * number. Elsewhere the two texts are the same (DoubleTextSpec checks both against BigDecimal).
 *
 * Method: Raffaello Giulietti's Schubfach ("The Schubfach way to render doubles", 2020), the algorithm of JDK
 * 19's `DoubleToDecimal`: the rounding interval of the double, scaled by 10^-k with a 126-bit approximation
 * of 10^-k, rounded to odd, decides between the at most two candidates of each length.
 */
object DoubleText {
  private final val Precision = 53 // significand bits of a double, with the hidden one
  private final val QMin = -1074 // exponent of the least significant bit of the smallest doubles
  private final val CMin = 1L << (Precision - 1) // the hidden bit
  private final val Mask63 = (1L << 63) - 1
  private final val KMin = -324 // the range of the decimal exponent k = floor(log10(2^q)) over normal doubles
  private final val KMax = 292

  /** floor(e * log10(2)), for |e| <= 5456721. */
  private def flog10pow2(e: Int): Int = ((e.toLong * 661971961083L) >> 41).toInt

  /** floor(log10(3/4 * 2^e)), for |e| <= 5456721. */
  private def flog10threeQuartersPow2(e: Int): Int = ((e.toLong * 661971961083L - 274743187321L) >> 41).toInt

  /** floor(e * log2(10)), for |e| <= 1838394. */
  private def flog2pow10(e: Int): Int = ((e.toLong * 913124641741L) >> 38).toInt

  /**
   * g(k) = floor(10^-k * 2^(125 - flog2pow10(-k))) + 1, a 126-bit number just above 10^-k scaled into [2^125,
   * 2^126], as its high and low 63 bits (computed once, exactly, in BigInteger).
   */
  private val (g1, g0): (Array[Long], Array[Long]) = {
    val ks = KMin to KMax
    val g = ks.map { k =>
      val e = flog2pow10(-k)
      val numerator = BigInteger.TEN.pow(math.max(-k, 0)).shiftLeft(math.max(125 - e, 0))
      val denominator = BigInteger.TEN.pow(math.max(k, 0)).shiftLeft(math.max(e - 125, 0))
      numerator.divide(denominator).add(BigInteger.ONE)
    }
    (
      g.map(_.shiftRight(63).longValueExact).toArray,
      g.map(_.and(BigInteger.valueOf(Mask63)).longValueExact).toArray
    )
  }

  /** 10^0 to 10^18, every power of ten a long holds (digit counts here, digit groups in [[FixedDecimal]]). */
  private[sim] val pow10: Array[Long] = Array.iterate(1L, 19)(_ * 10)

  /** Append the text of `x` to `text`. */
  def append(text: java.lang.StringBuilder, x: Double): java.lang.StringBuilder = {
    val bits = java.lang.Double.doubleToRawLongBits(x)
    val biasedExponent = ((bits >>> (Precision - 1)) & 0x7ff).toInt
    val fraction = bits & (CMin - 1)
    if (biasedExponent == 0 && fraction == 0) text.append(if (bits < 0) "-0.0" else "0.0")
    else if (biasedExponent == 0 || biasedExponent == 0x7ff) text.append(x) // subnormal, infinite or NaN
    else {
      if (bits < 0) text.append('-')
      val c = CMin | fraction
      val q = biasedExponent + QMin - 1 // |x| = c * 2^q
      // An integer below 2^53 is written with its own digits.
      if (q < 0 && q > -Precision && ((c >> -q) << -q) == c) layout(text, c >> -q, 0)
      else shortest(text, q, c)
    }
  }

  /** The text of `x` as a String. */
  def format(x: Double): String = append(new java.lang.StringBuilder, x).toString

  /** The shortest nearest decimal of c * 2^q (c a normal significand), laid out. */
  private def shortest(text: java.lang.StringBuilder, q: Int, c: Long): java.lang.StringBuilder = {
    val odd = (c & 1).toInt // an odd significand's interval excludes its ends (ties round to even)
    // The rounding interval [cbl, cbr] * 2^(q-2) around cb * 2^(q-2); narrower below a power of two.
    val cb = c << 2
    val cbr = cb + 2
    val symmetric = c != CMin || q == QMin
    val cbl = if (symmetric) cb - 2 else cb - 1
    val k = if (symmetric) flog10pow2(q) else flog10threeQuartersPow2(q)
    val h = q + flog2pow10(-k) + 2
    val (hi, lo) = (g1(k - KMin), g0(k - KMin))
    // 4 * (interval ends and centre) * 10^-k, rounded to odd.
    val vb = roundToOdd(hi, lo, cb << h)
    val vbl = roundToOdd(hi, lo, cbl << h)
    val vbr = roundToOdd(hi, lo, cbr << h)
    val s = vb >> 2
    if (s >= 100) {
      // One digit fewer: the multiples of ten around s (s / 10 by a multiply).
      val sp10 = 10 * multiplyHigh(s, 115292150460684698L << 4)
      val tp10 = sp10 + 10
      val lowerIn = vbl + odd <= (sp10 << 2)
      val upperIn = (tp10 << 2) + odd <= vbr
      if (lowerIn != upperIn) return layout(text, if (lowerIn) sp10 else tp10, k)
    }
    val t = s + 1
    val lowerIn = vbl + odd <= (s << 2)
    val upperIn = (t << 2) + odd <= vbr
    if (lowerIn != upperIn) return layout(text, if (lowerIn) s else t, k)
    // Both (or, by the paper, never neither): the nearer, ties to even.
    val cmp = vb - ((s + t) << 1)
    layout(text, if (cmp < 0 || (cmp == 0 && (s & 1) == 0)) s else t, k)
  }

  /** floor(g * cp / 2^127), its last bit set when the discarded bits are not all zero; g = hi * 2^63 + lo. */
  private def roundToOdd(hi: Long, lo: Long, cp: Long): Long = {
    val x1 = multiplyHigh(lo, cp)
    val y0 = hi * cp
    val y1 = multiplyHigh(hi, cp)
    val z = (y0 >>> 1) + x1
    val vbp = y1 + (z >>> 63)
    vbp | (((z & Mask63) + Mask63) >>> 63)
  }

  /** Append f * 10^e (f > 0) in `Double.toString`'s layout. */
  private def layout(text: java.lang.StringBuilder, digits: Long, exponent: Int): java.lang.StringBuilder = {
    var f = digits
    var e = exponent
    while (f % 10 == 0) { f /= 10; e += 1 }
    var n = 1
    while (n < pow10.length && f >= pow10(n)) n += 1
    val d = new Array[Char](n)
    var i = n
    while (i > 0) { i -= 1; d(i) = ('0' + f % 10).toChar; f /= 10 }
    val point = n + e // the value is 0.d1d2...dn * 10^point
    if (point > 0 && point <= 7) {
      if (n <= point) {
        text.append(d, 0, n)
        var z = n
        while (z < point) { text.append('0'); z += 1 }
        text.append(".0")
      } else text.append(d, 0, point).append('.').append(d, point, n - point)
    } else if (point > -3 && point <= 0) {
      text.append("0.")
      var z = point
      while (z < 0) { text.append('0'); z += 1 }
      text.append(d, 0, n)
    } else {
      text.append(d(0)).append('.')
      if (n > 1) text.append(d, 1, n - 1) else text.append('0')
      text.append('E').append(point - 1)
    }
  }
}
