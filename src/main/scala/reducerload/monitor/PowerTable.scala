package reducerload.monitor

/**
 * |tau|^p on unsigned torque magnitude codes, by linear interpolation between 2^segmentBits + 1
 * tabulated points. The input is a magnitude code `a` of `codeBits` bits standing for
 * u = a / 2^codeBits in [0, 1) (full scale = the torque format's 2^intBits N·m); the output is
 * a code of u^p with `fracBits` fraction bits (so at most 2^fracBits - 1).
 *
 * Normalising to full scale keeps every width independent of units and exponent: the damage sum
 * holds sum |qd| u^p, and the host multiplies by (full scale)^p once.
 *
 * Integer rule (the RTL does exactly this, [[ReducerMonitor]]'s joints read [[base]] and [[delta]]):
 *   k = a >> offsetBits, r = (a mod 2^offsetBits) >> droppedBits,
 *   power(a) = base(k) + floor((delta(k) * r + 2^(usedOffsetBits-1)) / 2^usedOffsetBits)
 * (the interpolated step rounded half up: no bias; it never passes the next point, so no clamp)
 *
 * @param exponent    life exponent p in [1, 10]
 * @param codeBits    bits of the magnitude code (torque width - 1)
 * @param segmentBits log2 of the number of segments
 * @param fracBits    fraction bits of u^p
 */
final case class PowerTable(exponent: Double, codeBits: Int, segmentBits: Int, fracBits: Int) {
  require(exponent >= 1.0 && exponent <= 10.0, s"PowerTable: exponent must be in [1, 10], got $exponent")
  require(segmentBits >= 1 && segmentBits <= 12, s"PowerTable: segmentBits must be in 1..12, got $segmentBits")
  require(codeBits > segmentBits, s"PowerTable: a $codeBits-bit magnitude leaves no offset bits below $segmentBits segment bits")
  require(fracBits >= 8 && fracBits <= 30, s"PowerTable: fracBits must be in 8..30, got $fracBits")

  val segments: Int = 1 << segmentBits

  /** Bits of the offset inside a segment, and how many of them feed the multiplier (17: one 18x18 block). */
  val offsetBits: Int = codeBits - segmentBits
  val usedOffsetBits: Int = offsetBits.min(PowerTable.maxOffsetBits)
  val droppedBits: Int = offsetBits - usedOffsetBits

  private val one = BigInt(1) << fracBits
  private def exact(u: Double): Double = math.pow(u, exponent)

  /** u^p at the segment ends, rounded to nearest, kept below 1.0 so a result needs only `fracBits` bits. */
  private val points: IndexedSeq[BigInt] = (0 to segments).map { k =>
    (BigDecimal(exact(k.toDouble / segments)) * BigDecimal(one)).setScale(0, BigDecimal.RoundingMode.HALF_UP).toBigInt.min(one - 1)
  }
  val base: IndexedSeq[BigInt] = points.init
  val delta: IndexedSeq[BigInt] = points.zip(points.tail).map { case (a, b) => b - a }

  val baseBits: Int = fracBits

  /** Half an LSB of the interpolated step, for rounding half up. */
  val half: BigInt = BigInt(1) << (usedOffsetBits - 1)
  val deltaBits: Int = delta.max.bitLength.max(1)

  /** The integer rule above: the model of the RTL's interpolation. */
  def power(a: BigInt): BigInt = {
    require(a >= 0 && a.bitLength <= codeBits, s"PowerTable.power: magnitude code $a does not fit $codeBits bits")
    val k = (a >> offsetBits).toInt
    val r = (a & ((BigInt(1) << offsetBits) - 1)) >> droppedBits
    base(k) + ((delta(k) * r + half) >> usedOffsetBits)
  }

  /** Exact u^p of a magnitude code. */
  def exactPower(a: BigInt): Double = exact(a.toDouble / math.pow(2.0, codeBits))

  /**
   * Bound on |power(a) / 2^fracBits - exactPower(a)| over every code, per segment then the max:
   * the chord's distance from the convex u^p (largest where the slope of u^p equals the chord's),
   * the end points' rounding (half an LSB; one at u = 1, kept below 1.0), which interpolation
   * does not enlarge, the dropped offset bits
   * (the point moves left by less than 2^droppedBits codes) and the step's rounding (half an LSB).
   */
  val errorBound: Double = {
    val lsb = 1.0 / one.toDouble
    val h = 1.0 / segments
    (0 until segments).map { k =>
      val (x0, x1) = (k * h, (k + 1) * h)
      val slope = (exact(x1) - exact(x0)) / h
      val chord =
        if (exponent == 1.0) 0.0
        else {
          val u = math.pow(slope / exponent, 1.0 / (exponent - 1.0)).max(x0).min(x1)
          exact(x0) + slope * (u - x0) - exact(u)
        }
      val dropped = delta(k).toDouble * lsb * ((BigInt(1) << droppedBits) - 1).toDouble / math.pow(2.0, offsetBits.toDouble)
      val ends = Seq(k, k + 1).map(i => math.abs(points(i).toDouble * lsb - exact(i * h))).max
      chord + ends + dropped + 0.5 * lsb
    }.max
  }

  /** Block memory bits of the table (base and delta words). */
  val memoryBits: Int = segments * (baseBits + deltaBits)
}

object PowerTable {

  /** Offset bits that still fit an 18x18 signed multiplier as a zero-extended operand. */
  val maxOffsetBits = 17
}
