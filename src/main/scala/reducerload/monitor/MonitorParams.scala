package reducerload.monitor

import reducerload.fixedpoint.FixedFormat
import reducerload.pipeline.PipelinedMultiplier

/**
 * Generator parameters of [[ReducerMonitor]]. Every per-joint parameter is a Seq whose length is the joint
 * count; nothing else states it. Every width, threshold code, bin edge and the power table are derived here
 * once, and both the RTL and [[MonitorModel]] read them.
 *
 * @param jointNames
 *   one name per joint (register names, reports)
 * @param torqueFormats
 *   format of each joint's torque input (raw SInt codes, N·m, as the datapath emits)
 * @param velocityFormats
 *   format of each joint's velocity input (raw SInt codes, rad/s at the reducer output)
 * @param repeatedPeakNm
 *   T_R per joint (N·m): a sample counts when |tau| > T_R (strictly)
 * @param momentaryPeakNm
 *   T_M per joint (N·m): an event is a run of consecutive valid samples with |tau| > T_M
 * @param lifeExponents
 *   p per joint in [1, 10]: 3 for strain-wave (Harmonic Drive), 10/3 for cycloidal (RV)
 * @param gearRatios
 *   reduction ratio i per joint (input speed = i x output speed), for the life formula
 * @param histogramBins
 *   number of |tau| bins per joint; the last bin takes everything above its lower edge
 * @param histogramBinWidthNm
 *   bin width per joint (N·m); bin k holds k w <= |tau| < (k+1) w
 * @param samplePeriodS
 *   time between valid samples (s): dt of the damage sums and the basis of the 20-year proof
 * @param targetYears
 *   run time every accumulator must hold without overflow
 * @param histogramCounterBits
 *   width of the saturating histogram counters (None: sized for `targetYears`, never saturate)
 * @param powerFracBits
 *   bits of the |tau|^p mantissa (the damage multiply's operand; [[PowerTable]])
 * @param powerSegmentBits
 *   log2 of the interpolation segments per octave of the power table
 * @param powerRangeBits
 *   the power table is relative down to u^p = 2^-powerRangeBits (u = |tau| / full scale), absolute below; the
 *   damage sums are this many bits wider
 * @param testStartAfterSamples
 *   test only: clear and reset load every proven accumulator with the value it would hold after this many
 *   worst-case samples, so a short simulation reaches the top bits of the 20-year widths. None in every real
 *   build.
 */
final case class MonitorParams(
    jointNames: Seq[String],
    torqueFormats: Seq[FixedFormat],
    velocityFormats: Seq[FixedFormat],
    repeatedPeakNm: Seq[Double],
    momentaryPeakNm: Seq[Double],
    lifeExponents: Seq[Double],
    gearRatios: Seq[Double],
    histogramBins: Seq[Int],
    histogramBinWidthNm: Seq[Double],
    samplePeriodS: Double,
    targetYears: Double = 20.0,
    histogramCounterBits: Option[Int] = None,
    powerFracBits: Int = 17,
    powerSegmentBits: Int = 6,
    powerRangeBits: Int = 40,
    testStartAfterSamples: Option[BigInt] = None
) {

  require(jointNames.nonEmpty, "MonitorParams.jointNames: at least one joint")

  /** Joint count: the length of every per-joint Seq. */
  val joints: Int = jointNames.size
  Seq(
    "torqueFormats" -> torqueFormats.size,
    "velocityFormats" -> velocityFormats.size,
    "repeatedPeakNm" -> repeatedPeakNm.size,
    "momentaryPeakNm" -> momentaryPeakNm.size,
    "lifeExponents" -> lifeExponents.size,
    "gearRatios" -> gearRatios.size,
    "histogramBins" -> histogramBins.size,
    "histogramBinWidthNm" -> histogramBinWidthNm.size
  ).foreach { case (name, size) =>
    require(
      size == joints,
      s"MonitorParams.$name has $size entries for $joints joints (${jointNames.mkString(", ")})"
    )
  }
  require(
    jointNames.forall(n => n.matches("[A-Za-z_][A-Za-z0-9_]*")),
    s"MonitorParams.jointNames must be identifiers (letters, digits, _), got ${jointNames.mkString(", ")}"
  )
  require(
    jointNames.distinct.size == joints,
    s"MonitorParams.jointNames must be distinct, got ${jointNames.mkString(", ")}"
  )
  private def finite(x: Double) = !x.isNaN && !x.isInfinite
  require(
    finite(samplePeriodS) && samplePeriodS >= 1e-9 && samplePeriodS <= 10.0,
    s"MonitorParams.samplePeriodS must be in [1e-9, 10] s, got $samplePeriodS"
  )
  require(
    finite(targetYears) && targetYears > 0 && targetYears <= 100,
    s"MonitorParams.targetYears must be in (0, 100], got $targetYears"
  )
  require(
    powerFracBits >= 8 && powerFracBits <= 30,
    s"MonitorParams.powerFracBits must be in 8..30, got $powerFracBits"
  )
  require(
    powerSegmentBits >= 1 && powerSegmentBits <= 12,
    s"MonitorParams.powerSegmentBits must be in 1..12, got $powerSegmentBits"
  )
  require(
    powerRangeBits >= 1 && powerRangeBits <= 120,
    s"MonitorParams.powerRangeBits must be in 1..120, got $powerRangeBits"
  )

  /** Full scale of each torque format (N·m): |tau| codes are normalised to it for the power table. */
  val torqueFullScaleNm: Seq[Double] = torqueFormats.map(f => math.pow(2.0, f.intBits))

  (0 until joints).foreach { j =>
    def bad(param: String, what: String) = s"MonitorParams: joint ${j + 1} (${jointNames(j)}): $param $what"
    val (tf, vf) = (torqueFormats(j), velocityFormats(j))
    require(
      tf.width >= 4 && tf.width <= 48,
      bad("torqueFormats", s"must be 4..48 bits wide, got $tf (${tf.width} bits)")
    )
    require(
      tf.width - 1 >= powerSegmentBits + 2,
      bad(
        "torqueFormats",
        s"$tf has ${tf.width - 1} magnitude bits, fewer than powerSegmentBits ($powerSegmentBits) + 2 " +
          s"(leading one and an offset bit)"
      )
    )
    require(
      vf.width >= 2 && vf.width <= 48,
      bad("velocityFormats", s"must be 2..48 bits wide, got $vf (${vf.width} bits)")
    )
    val (tr, tm) = (repeatedPeakNm(j), momentaryPeakNm(j))
    require(finite(tr) && tr > 0, bad("repeatedPeakNm", s"(T_R) must be a positive number, got $tr"))
    require(
      finite(tm) && tm > tr,
      bad("momentaryPeakNm", s"(T_M) must exceed repeatedPeakNm (T_R = $tr), got $tm")
    )
    require(
      tm < tf.maxValue,
      bad(
        "momentaryPeakNm",
        s"(T_M = $tm N·m) must be below the torque format's maximum ${tf.maxValue} N·m ($tf)"
      )
    )
    val p = lifeExponents(j)
    require(finite(p) && p >= 1.0 && p <= 10.0, bad("lifeExponents", s"(p) must be in [1, 10], got $p"))
    val i = gearRatios(j)
    require(finite(i) && i > 0, bad("gearRatios", s"must be a positive number, got $i"))
    val (bins, width) = (histogramBins(j), histogramBinWidthNm(j))
    require(bins >= 1 && bins <= 256, bad("histogramBins", s"must be in 1..256, got $bins"))
    require(
      finite(width) && width >= tf.lsb,
      bad("histogramBinWidthNm", s"must be at least one torque LSB (${tf.lsb} N·m), got $width")
    )
    require(
      (bins - 1) * width < tf.maxValue,
      bad(
        "histogramBinWidthNm",
        s"x (histogramBins - 1) = ${(bins - 1) * width} N·m puts the last bin above the torque " +
          s"format's maximum ${tf.maxValue} N·m"
      )
    )
  }
  histogramCounterBits.foreach(b =>
    require(b >= 1 && b <= 64, s"MonitorParams.histogramCounterBits must be in 1..64, got $b")
  )

  // ---- thresholds and bins, in codes ----
  private def codeFloor(nm: Double, f: FixedFormat): BigInt =
    (BigDecimal(nm) * BigDecimal(2).pow(f.fracBits)).setScale(0, BigDecimal.RoundingMode.FLOOR).toBigInt
  private def codeCeil(nm: Double, f: FixedFormat): BigInt =
    (BigDecimal(nm) * BigDecimal(2).pow(f.fracBits)).setScale(0, BigDecimal.RoundingMode.CEILING).toBigInt

  /** |tau| code > this  <=>  |tau| > T_R (N·m, as written in decimal). */
  val repeatedPeakCode: Seq[BigInt] =
    (0 until joints).map(j => codeFloor(repeatedPeakNm(j), torqueFormats(j)))
  val momentaryPeakCode: Seq[BigInt] =
    (0 until joints).map(j => codeFloor(momentaryPeakNm(j), torqueFormats(j)))

  /**
   * Lower edge of each bin in |tau| codes: code c is in bin k when edge(k) <= c < edge(k + 1). edge(0) = 0.
   */
  val binEdges: Seq[IndexedSeq[BigInt]] =
    (0 until joints).map(j =>
      (0 until histogramBins(j)).map(k => codeCeil(k * histogramBinWidthNm(j), torqueFormats(j)))
    )
  (0 until joints).foreach { j =>
    require(
      binEdges(j).zip(binEdges(j).drop(1)).forall { case (a, b) => a < b },
      s"MonitorParams: joint ${j + 1} (${jointNames(j)}): histogramBinWidthNm ${histogramBinWidthNm(j)} " +
        s"gives two bin edges on one code"
    )
  }

  /** The bin of a |tau| code: the same rule as the RTL's comparisons against the edges. */
  def binOf(joint: Int, absCode: BigInt): Int = binEdges(joint).lastIndexWhere(_ <= absCode)

  // ---- magnitudes and the power table ----
  /** Magnitude codes saturate at the format's max (only the most negative code is affected). */
  val torqueMagnitudeBits: Seq[Int] = torqueFormats.map(_.width - 1)
  val velocityMagnitudeBits: Seq[Int] = velocityFormats.map(_.width - 1)
  def magnitude(raw: BigInt, f: FixedFormat): BigInt = raw.abs.min(f.maxRaw)

  val powerTables: Seq[PowerTable] =
    (0 until joints).map(j =>
      PowerTable(lifeExponents(j), torqueMagnitudeBits(j), powerSegmentBits, powerFracBits, powerRangeBits)
    )

  /** |power / 2^valueFracBits - u^p| <= relative x u^p + absolute for every code (u = |tau| / full scale). */
  val powerRelativeBound: Seq[Double] = powerTables.map(_.relativeBound)
  val powerAbsoluteBound: Seq[Double] = powerTables.map(_.absoluteBound)

  /** Largest power value (the damage increment's factor). */
  val maxPowerCode: Seq[BigInt] = powerTables.map(_.maxPower)

  // ---- the 20-year proof ----
  val secondsPerYear: Double = 365.25 * 86400.0

  /** Valid samples in `targetYears` at one per `samplePeriodS`: every count below is at most this. */
  val sampleBudget: BigInt =
    (BigDecimal(targetYears) * BigDecimal(secondsPerYear) / BigDecimal(samplePeriodS))
      .setScale(0, BigDecimal.RoundingMode.CEILING)
      .toBigInt

  /** Largest increment per sample of each proven accumulator of joint `j`. */
  def maxIncrement(j: Int, field: JointField): BigInt = field match {
    case JointField.DamageSum => velocityFormats(j).maxRaw * maxPowerCode(j)
    case JointField.SpeedSum  => velocityFormats(j).maxRaw
    case JointField.Samples | JointField.OutOfRangeSamples | JointField.RepeatedPeakSamples |
        JointField.MomentaryPeakEvents | JointField.LastEventDuration =>
      BigInt(1)
    case other => throw new IllegalArgumentException(s"${other.name} is not an accumulator")
  }
  val provenAccumulators: Seq[JointField] = Seq(
    JointField.Samples,
    JointField.OutOfRangeSamples,
    JointField.RepeatedPeakSamples,
    JointField.MomentaryPeakEvents,
    JointField.LastEventDuration,
    JointField.DamageSum,
    JointField.SpeedSum
  )

  /** Unsigned width: the largest `targetYears` total, max increment x sample budget, is below 2^width. */
  def accumulatorBits(j: Int, field: JointField): Int = (maxIncrement(j, field) * sampleBudget).bitLength

  val histogramBitsPerJoint: Int = histogramCounterBits.getOrElse(sampleBudget.bitLength)
  def histogramMax: BigInt = (BigInt(1) << histogramBitsPerJoint) - 1

  testStartAfterSamples.foreach(s =>
    require(
      s >= 0 && s <= sampleBudget,
      s"MonitorParams.testStartAfterSamples must be in 0..$sampleBudget (the sample budget), got $s"
    )
  )

  /** Value of a proven accumulator after clear: 0, or the test preset. */
  def clearValue(j: Int, field: JointField): BigInt =
    testStartAfterSamples.fold(BigInt(0))(_ * maxIncrement(j, field))

  /** Test preset also starts a momentary-peak event that has lasted the preset's samples. */
  val clearInEvent: Boolean = testStartAfterSamples.exists(_ > 0)

  /** Bit width of every register of joint `j`. */
  def fieldWidth(j: Int, field: JointField): Int = field match {
    case JointField.PeakTorque | JointField.MinTorque => torqueFormats(j).width
    case JointField.LastEventPeak                     => torqueMagnitudeBits(j)
    case JointField.LastEventSpeed                    => velocityMagnitudeBits(j)
    case JointField.Flags                             => JointField.FlagBit.count
    case JointField.HistogramBin(_)                   => histogramBitsPerJoint
    case f                                            => accumulatorBits(j, f)
  }
  def fieldSigned(field: JointField): Boolean =
    field == JointField.PeakTorque || field == JointField.MinTorque
  def fields(j: Int): Seq[JointField] =
    JointField.scalars ++ (0 until histogramBins(j)).map(JointField.HistogramBin)

  /** The proof for reports: the budget, then per joint the counters (max 1 per sample) and the two sums. */
  def proofLines: Seq[String] = {
    val counters = provenAccumulators.filter(f => maxIncrement(0, f) == 1)
    val sums = provenAccumulators.filterNot(counters.contains)
    (f"sample budget N = $targetYears%.4g years x ${secondsPerYear}%.0f s / $samplePeriodS%.6g s = " +
      f"$sampleBudget valid samples (one per sample period)") +:
      (0 until joints).map { j =>
        val c =
          s"${counters.map(_.name).mkString(", ")}: max 1 per sample, N < " +
            s"2^${accumulatorBits(j, counters.head)} (${accumulatorBits(j, counters.head)} bits)"
        val ss = sums.map { f =>
          s"${f.name}: max ${maxIncrement(j, f)} per sample, x N = ${maxIncrement(j, f) * sampleBudget} < " +
            s"2^${accumulatorBits(j, f)} (${accumulatorBits(j, f)} bits)"
        }
        (s"${jointNames(j)}: $c" +: ss).mkString("; ")
      }
  }

  // ---- register map ----
  val registerMap: RegisterMap = RegisterMap.layout(
    Seq[(RegisterKey, String, Int, Boolean, String)](
      (RegisterKey.Id, "monitor_id", 32, false, s"0x524D0000 + joint count (${joints})"),
      (RegisterKey.SnapshotCount, "snapshot_count", 32, false, "snapshots taken since reset, modulo 2^32")
    ) ++ (0 until joints).flatMap { j =>
      fields(j).map(f =>
        (RegisterKey.Joint(j, f), s"${jointNames(j)}.${f.name}", fieldWidth(j, f), fieldSigned(f), f.meaning)
      )
    }
  )

  /** Word-address bits of the read port. */
  val addressBits: Int = BigInt(registerMap.words - 1).bitLength.max(1)

  // ---- pipeline schedule (the same for every joint: the longest one) ----
  def interpolationMulWidths(j: Int): (Int, Int) =
    (powerTables(j).deltaBits + 1, powerTables(j).usedOffsetBits + 1)
  def damageMulWidths(j: Int): (Int, Int) = (velocityMagnitudeBits(j) + 1, powerFracBits + 1)

  /** Cycle (after the input) at which the power mantissa of joint `j` is registered. */
  def powerReadyAt(j: Int): Int = {
    val (a, b) = interpolationMulWidths(j); 6 + PipelinedMultiplier.latency(a, b)
  }

  /**
   * Cycle at which joint `j`'s damage increment (the product shifted by the segment's exponent) is
   * registered.
   */
  def damageReadyAt(j: Int): Int = {
    val (a, b) = damageMulWidths(j); powerReadyAt(j) + PipelinedMultiplier.latency(a, b) + 1
  }

  /**
   * Cycle at which every joint's state is updated by a sample (and by snapshot/clear) of input cycle t: t +
   * updateStage. Stages: 1 input registers, 2 magnitudes, 3 region (leading one) and comparisons, 4
   * normalising shift, 5 table read, interpolation multiply, mantissa register, damage multiply, exponent
   * shift.
   */
  val updateStage: Int = (0 until joints).map(damageReadyAt).max

  /**
   * A snapshot pulsed at input cycle t is in the shadow bank from cycle t + snapshotLatency (and snapshotDone
   * is high then).
   */
  val snapshotLatency: Int = updateStage + 1

  /** 18x18 multiplier blocks per joint (interpolation and damage). */
  def multiplierBlocks(j: Int): Int = {
    val ((a, b), (c, d)) = (interpolationMulWidths(j), damageMulWidths(j))
    PipelinedMultiplier.blocks(a, b) + PipelinedMultiplier.blocks(c, d)
  }

  /** The whole derivation as text lines for reports and the emitted header. */
  def summaryLines: Seq[String] =
    Seq(
      f"joints: $joints, sample period $samplePeriodS%.6g s, update stage $updateStage, snapshot " +
        f"latency $snapshotLatency cycles, " +
        s"register bank ${registerMap.words} words ($addressBits address bits)"
    ) ++
      (0 until joints).map { j =>
        val t = powerTables(j)
        f"${jointNames(j)}: torque ${torqueFormats(j)}, velocity ${velocityFormats(j)}, T_R " +
          f"${repeatedPeakNm(j)} N·m (code > ${repeatedPeakCode(j)}), T_M ${momentaryPeakNm(j)} N·m (code " +
          f"> ${momentaryPeakCode(j)}), p ${lifeExponents(j)}%.6g, i ${gearRatios(j)}, ${histogramBins(j)} " +
          f"bins of ${histogramBinWidthNm(j)} N·m, ${t.describe} (u = |tau| / " +
          f"${torqueFullScaleNm(j)}%.0f N·m), ${multiplierBlocks(j)} multiplier blocks"
      } ++ proofLines
}

object MonitorParams {

  /** The same limits and settings for every joint but the names and formats. */
  def uniform(
      jointNames: Seq[String],
      torqueFormat: FixedFormat,
      velocityFormat: FixedFormat,
      repeatedPeakNm: Double,
      momentaryPeakNm: Double,
      samplePeriodS: Double,
      lifeExponent: Double = 3.0,
      gearRatio: Double = 100.0,
      histogramBins: Int = 16,
      histogramBinWidthNm: Double = 10.0
  ): MonitorParams = {
    val n = jointNames.size
    MonitorParams(
      jointNames,
      Seq.fill(n)(torqueFormat),
      Seq.fill(n)(velocityFormat),
      Seq.fill(n)(repeatedPeakNm),
      Seq.fill(n)(momentaryPeakNm),
      Seq.fill(n)(lifeExponent),
      Seq.fill(n)(gearRatio),
      Seq.fill(n)(histogramBins),
      Seq.fill(n)(histogramBinWidthNm),
      samplePeriodS
    )
  }

  /**
   * The documented example (docs/monitor.md): a UR5-sized 6-axis arm at 1 kHz, strain-wave reducers (p = 3, i
   * \= 101); the three big joints Q8.20 (+-256 N·m), the wrist Q6.20 (+-64 N·m); velocities Q2.20 (+-4
   * rad/s). Limits illustrative (CSD-25/20/17-class ratings).
   */
  def example(samplePeriodS: Double = 1e-3): MonitorParams = {
    val big = FixedFormat(8, 20)
    val wrist = FixedFormat(6, 20)
    MonitorParams(
      jointNames = Seq("shoulder_pan", "shoulder_lift", "elbow", "wrist_1", "wrist_2", "wrist_3"),
      torqueFormats = Seq(big, big, big, wrist, wrist, wrist),
      velocityFormats = Seq.fill(6)(FixedFormat(2, 20)),
      repeatedPeakNm = Seq(150.0, 150.0, 150.0, 28.0, 28.0, 28.0),
      momentaryPeakNm = Seq(230.0, 230.0, 230.0, 54.0, 54.0, 54.0),
      lifeExponents = Seq.fill(6)(3.0),
      gearRatios = Seq.fill(6)(101.0),
      histogramBins = Seq(16, 16, 16, 16, 16, 16),
      histogramBinWidthNm = Seq(16.0, 16.0, 16.0, 4.0, 4.0, 4.0),
      samplePeriodS = samplePeriodS
    )
  }
}
