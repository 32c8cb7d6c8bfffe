package reducerload.monitor

/**
 * \|tau|^p on unsigned torque magnitude codes with an error relative to the load: a piecewise-linear table in
 * floating-point form (a mantissa and a power-of-two scale per segment), evaluated in exact integer
 * arithmetic. The input is a magnitude code `a` of n = `codeBits` bits standing for u = a / 2^n in [0, 1)
 * (full scale = the torque format's 2^intBits N·m).
 *
 * Regions (by the position of the leading one, K = [[octaves]]):
 *   - region r = 1..K: the octave 2^(n-K+r-1) <= a < 2^(n-K+r), i.e. 2^(r-K-1) <= u < 2^(r-K);
 *   - region 0: a < 2^(n-K) (u < 2^-K), the floor, where the error is absolute.
 * Each region is normalised by a left shift sh(r) = K - max(r, 1), so its codes fill the same n bits (a
 * leading one at bit n-1 for r >= 1, below it for region 0), and is cut into 2^k segments (k = `segmentBits`)
 * by the k bits below bit n-1; the n-1-k bits under them are the offset. Segment s covers u in [x0, x1] and
 * has its own exponent E_s: the least E with x1^p <= 2^E (region 0: the exponent of (2^-K)^p for all its
 * segments, E_0). Its end points are tabulated as mantissas M(x) = round(x^p 2^(F - E_s)) (F = `fracBits`,
 * capped at 2^F - 1) and shift(s) = E_s - E_0 >= 0.
 *
 * Integer rule (the RTL does exactly this, [[JointMonitor]] reads [[base]], [[delta]] and [[shift]]): region,
 * sh from the leading one; a' = a << sh; s = region 2^k + bits n-2 .. n-1-k of a'; r = (a' mod 2^offsetBits)
 * >> droppedBits, mantissa(a) = base(s) + floor((delta(s) r + 2^(usedOffsetBits-1)) / 2^usedOffsetBits) (<
 * 2^F), power(a) = mantissa(a) << shift(s), a value of u^p with [[valueFracBits]] = F - E_0 fraction bits.
 * The damage increment |qd| x power is then the F-bit mantissa product shifted left: the multiplier stays one
 * 18x18 operand wide while every load keeps about F significant bits.
 *
 * @param exponent
 *   life exponent p in [1, 10]
 * @param codeBits
 *   bits of the magnitude code (torque width - 1)
 * @param segmentBits
 *   log2 of the segments per region
 * @param fracBits
 *   bits of the mantissa (one multiplier operand)
 * @param rangeBits
 *   the table is relative down to u^p = 2^-rangeBits: K = floor(rangeBits / p) octaves (at most codeBits -
 *   segmentBits); it sets the damage sum's extra width (E_0 = -floor(p K) or so)
 */
final case class PowerTable(
    exponent: Double,
    codeBits: Int,
    segmentBits: Int,
    fracBits: Int,
    rangeBits: Int
) {
  require(exponent >= 1.0 && exponent <= 10.0, s"PowerTable: exponent must be in [1, 10], got $exponent")
  require(
    segmentBits >= 1 && segmentBits <= 12,
    s"PowerTable: segmentBits must be in 1..12, got $segmentBits"
  )
  require(
    codeBits >= segmentBits + 2,
    s"PowerTable: a $codeBits-bit magnitude leaves no offset bits below $segmentBits " +
      s"segment bits and the leading one"
  )
  require(fracBits >= 8 && fracBits <= 30, s"PowerTable: fracBits must be in 8..30, got $fracBits")
  require(rangeBits >= 1 && rangeBits <= 120, s"PowerTable: rangeBits must be in 1..120, got $rangeBits")

  /** Octave regions K (region 0 below them). */
  val octaves: Int = math.floor(rangeBits / exponent).toInt.max(1).min(codeBits - segmentBits)
  val regions: Int = octaves + 1
  val regionBits: Int = BigInt(octaves).bitLength
  val segmentsPerRegion: Int = 1 << segmentBits
  val segments: Int = regions * segmentsPerRegion

  /**
   * Bits of the offset inside a segment (after normalisation), and how many feed the multiplier (17: one
   * 18x18 block).
   */
  val offsetBits: Int = codeBits - 1 - segmentBits
  val usedOffsetBits: Int = offsetBits.min(PowerTable.maxOffsetBits)
  val droppedBits: Int = offsetBits - usedOffsetBits

  /** The lowest code of the octave regions: region 0 is every code below it. */
  val floorCode: BigInt = BigInt(1) << (codeBits - octaves)

  private def exact(u: Double): Double = math.pow(u, exponent)
  private def u(a: BigInt): Double = math.scalb(a.toDouble, -codeBits)

  /** Region of a magnitude code: 0 below [[floorCode]], else its octave 1..K. */
  def regionOf(a: BigInt): Int = (a.bitLength - (codeBits - octaves)).max(0)

  /** Left shift that normalises a code of region `r`. */
  def normalisingShift(r: Int): Int = octaves - r.max(1)

  /** Code range [x0, x1) of segment `s` (x1 is the next segment's first code, or 2^n). */
  private def codes(s: Int): (BigInt, BigInt) = {
    val (r, k) = (s / segmentsPerRegion, s % segmentsPerRegion)
    val sh = normalisingShift(r)
    val lead = if (r >= 1) BigInt(1) << (codeBits - 1) else BigInt(0)
    val x0 = (lead + (BigInt(k) << offsetBits)) >> sh
    (x0, x0 + ((BigInt(1) << offsetBits) >> sh))
  }

  /** Least E with y <= 2^E (y > 0). */
  private def exponentAbove(y: Double): Int = {
    val e = java.lang.Math.getExponent(y); if (y == math.scalb(1.0, e)) e else e + 1
  }

  /** E_0: region 0's exponent, the scale of the damage sum. */
  val floorExponent: Int = exponentAbove(exact(u(floorCode)))

  /** Exponent of each segment. */
  val exponents: IndexedSeq[Int] = (0 until segments).map { s =>
    if (s < segmentsPerRegion) floorExponent else exponentAbove(exact(u(codes(s)._2))).max(floorExponent)
  }

  private val mantissaMax = (BigInt(1) << fracBits) - 1
  private def mantissaAt(a: BigInt, e: Int): BigInt =
    BigDecimal(math.scalb(exact(u(a)), fracBits - e))
      .setScale(0, BigDecimal.RoundingMode.HALF_UP)
      .toBigInt
      .min(mantissaMax)

  val base: IndexedSeq[BigInt] = (0 until segments).map(s => mantissaAt(codes(s)._1, exponents(s)))
  val delta: IndexedSeq[BigInt] = (0 until segments).map(s => mantissaAt(codes(s)._2, exponents(s)) - base(s))
  val shift: IndexedSeq[Int] = exponents.map(_ - floorExponent)

  val baseBits: Int = fracBits
  val deltaBits: Int = delta.max.bitLength.max(1)
  val shiftBits: Int = BigInt(shift.max).bitLength.max(1)

  /** Fraction bits of [[power]]: value = power / 2^valueFracBits. */
  val valueFracBits: Int = fracBits - floorExponent

  /** Half an LSB of the interpolated step, for rounding half up. */
  val half: BigInt = BigInt(1) << (usedOffsetBits - 1)

  require(delta.forall(_ >= 0), "PowerTable: a segment's end points decrease")

  /** Segment (ROM address) and multiplier offset of a code: the RTL's normalisation and field split. */
  def locate(a: BigInt): (Int, BigInt) = {
    require(
      a >= 0 && a.bitLength <= codeBits,
      s"PowerTable.power: magnitude code $a does not fit $codeBits bits"
    )
    val r = regionOf(a)
    val normal = a << normalisingShift(r)
    val k = ((normal >> offsetBits) & (segmentsPerRegion - 1)).toInt
    (r * segmentsPerRegion + k, (normal & ((BigInt(1) << offsetBits) - 1)) >> droppedBits)
  }

  /** The F-bit mantissa of a code (the interpolation). */
  def mantissa(a: BigInt): BigInt = {
    val (s, r) = locate(a)
    base(s) + ((delta(s) * r + half) >> usedOffsetBits)
  }

  /** u^p of a code with [[valueFracBits]] fraction bits: the model of the RTL. */
  def power(a: BigInt): BigInt = mantissa(a) << shift(locate(a)._1)

  /** Exact u^p of a magnitude code. */
  def exactPower(a: BigInt): Double = exact(u(a))

  /** power(a) as u^p in a double: exact (a mantissa of at most `fracBits` significant bits, shifted). */
  def powerValue(a: BigInt): Double = math.scalb(power(a).toDouble, -valueFracBits)

  /** Largest power: the last code of some segment (the mantissa does not decrease inside a segment). */
  val maxPower: BigInt = (0 until segments).map(s => power(codes(s)._2 - 1)).max

  /**
   * Bound on |power(a) / 2^valueFracBits - exactPower(a)| in segment s, in u^p: the chord's distance from the
   * convex u^p (largest where the slope of u^p equals the chord's), the end points' rounding (half an LSB,
   * one at u = 1, kept below 2^F; interpolation does not enlarge it), the dropped offset bits (the point
   * moves left by less than 2^droppedBits offset units) and the step's rounding (half an LSB). LSB = 2^(E_s -
   * F).
   */
  private def segmentBound(s: Int): Double = {
    val (a0, a1) = codes(s)
    val (x0, x1) = (u(a0), u(a1))
    val lsb = math.scalb(1.0, exponents(s) - fracBits)
    val slope = (exact(x1) - exact(x0)) / (x1 - x0)
    val chord =
      if (exponent == 1.0) 0.0
      else {
        val t = math.pow(slope / exponent, 1.0 / (exponent - 1.0)).max(x0).min(x1)
        exact(x0) + slope * (t - x0) - exact(t)
      }
    val dropped =
      delta(s).toDouble * lsb * ((BigInt(1) << droppedBits) - 1).toDouble / math.scalb(1.0, offsetBits)
    val ends = Seq(a0 -> base(s), a1 -> (base(s) + delta(s))).map { case (a, m) =>
      math.abs(m.toDouble * lsb - exact(u(a)))
    }.max
    (chord + ends + dropped + 0.5 * lsb) * (1 + 1e-9)
  }

  /**
   * Relative part of the bound: for u >= 2^-K, |power - u^p| <= relativeBound x u^p (each segment's bound
   * over its smallest u^p).
   */
  val relativeBound: Double =
    (segmentsPerRegion until segments).map(s => segmentBound(s) / exact(u(codes(s)._1))).max

  /** Absolute part (region 0, u < 2^-K): |power - u^p| <= absoluteBound. */
  val absoluteBound: Double = (0 until segmentsPerRegion).map(segmentBound).max

  /** Bound on |power(a) / 2^valueFracBits - u^p| for every code: relativeBound u^p + absoluteBound. */
  def errorBound(a: BigInt): Double = relativeBound * exactPower(a) + absoluteBound

  /** Block memory bits of the table (base, delta and shift words). */
  val memoryBits: Int = segments * (baseBits + deltaBits + shiftBits)

  /** One line for reports. */
  def describe: String =
    f"power table $regions regions (u >= 2^-$octaves relative) x $segmentsPerRegion segments x " +
      f"${baseBits + deltaBits + shiftBits} bits, u^p = power / 2^$valueFracBits, |power / " +
      f"2^$valueFracBits - u^p| <= $relativeBound%.2e u^p + $absoluteBound%.2e"
}

object PowerTable {

  /** Offset bits that still fit an 18x18 signed multiplier as a zero-extended operand. */
  val maxOffsetBits = 17
}
