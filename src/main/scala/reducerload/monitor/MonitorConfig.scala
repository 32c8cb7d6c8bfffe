package reducerload.monitor

import reducerload.arm.ArmParams
import reducerload.config.MonitorSettings
import reducerload.fixedpoint.FixedFormat

/**
 * The monitor a configuration describes, resolved against the arm it watches: one value per joint, limits
 * from the URDF where asked, formats from the datapath. Every refusal names its key.
 *
 * Rules:
 *   - `urdf` limits: T_R = `<limit effort>` (a URDF's effort is the torque the joint is specified to deliver
 *     in normal operation, i.e. the peak of normal start/stop cycles: the repeated peak), and T_M =
 *     `monitor.momentary-peak-factor` x effort. The factor is a setting because catalogues differ (Harmonic
 *     Drive CSF/CSD tables put T_M near 2 x T_R); its default 1.5 is the conservative end and should be
 *     checked against the reducer's data sheet.
 *   - `auto` bin width: the joint's derived torque range (what the datapath can output for inputs in range) /
 *     bins, rounded up to three significant digits (a readable width; the bins still span the range). Any
 *     width works exactly: a code is in bin k when code >= ceil(k w 2^frac), i.e. when its value is >= k w.
 *   - torque formats: the datapath's per-joint output format, widened (sign extension, no cost in the
 *     datapath) when T_M or the last bin edge lies beyond it, since the monitor's thresholds must be
 *     representable; a T_M beyond the torque range is then simply never reached.
 *   - velocity formats: the datapath's per-joint formats of the clamped velocities.
 */
object MonitorConfig {

  /** Widest torque code the monitor accepts (MonitorParams' limit). */
  val maxTorqueWidth: Int = 48

  /** One value for every joint or one per joint. */
  def perJoint[T](arm: ArmParams, values: Seq[T], key: String): IndexedSeq[T] = values.size match {
    case 1                        => IndexedSeq.fill(arm.chain.size)(values.head)
    case n if n == arm.chain.size => values.toIndexedSeq
    case n =>
      throw new IllegalArgumentException(
        s"monitor.$key gives $n values, robot ${arm.chain.name} has ${arm.chain.size} joints (give one number or one per joint)"
      )
  }

  /** `<limit effort>` of every joint, or a message naming `key` and what to do. */
  private def efforts(arm: ArmParams, key: String): IndexedSeq[Double] = arm.chain.joints.map { j =>
    j.effortLimit.filter(_ > 0).getOrElse {
      if (arm.chain.name == reducerload.robot.Planar3.name)
        throw new IllegalArgumentException(
          s"monitor.$key = urdf, but planar3 has no URDF <limit effort>: give the limit in N·m (one number or one per joint)"
        )
      else
        throw new IllegalArgumentException(
          s"monitor.$key = urdf, but joint ${j.name} has no positive <limit effort> in the URDF: give the limit in N·m"
        )
    }
  }

  /** Register and port names must be identifiers: other characters of a joint name become '_'. */
  def identifier(name: String): String = {
    val cleaned = name.replaceAll("[^A-Za-z0-9_]", "_")
    if (cleaned.headOption.exists(_.isLetter) || cleaned.startsWith("_")) cleaned else s"j_$cleaned"
  }

  def apply(arm: ArmParams, s: MonitorSettings): MonitorParams = {
    val joints = arm.chain.joints.indices
    val names = arm.jointNames
    val repeated =
      if (s.repeatedPeakNm.isEmpty) efforts(arm, "repeated-peak")
      else perJoint(arm, s.repeatedPeakNm, "repeated-peak")
    val momentary =
      if (s.momentaryPeakNm.isEmpty) efforts(arm, "momentary-peak").map(_ * s.momentaryPeakFactor)
      else perJoint(arm, s.momentaryPeakNm, "momentary-peak")
    joints.foreach { j =>
      require(
        momentary(j) > repeated(j),
        s"monitor.momentary-peak (T_M = ${momentary(j)} N·m) must exceed monitor.repeated-peak (T_R = ${repeated(j)} N·m) for joint ${names(j)}"
      )
    }
    val bins = perJoint(arm, s.histogramBins, "histogram-bins")
    val outputFormats = arm.analysis.outputs.map(_.format)
    val widths =
      if (s.histogramBinWidthNm.isEmpty)
        joints.map(j => autoBinWidth(arm.analysis.outputs(j).range.maxAbs, bins(j), outputFormats(j).lsb))
      else perJoint(arm, s.histogramBinWidthNm, "histogram-bin-width")
    joints.foreach { j =>
      require(
        widths(j) >= outputFormats(j).lsb,
        s"monitor.histogram-bin-width (${widths(j)} N·m) must be at least one torque LSB (${outputFormats(j).lsb} N·m) for joint ${names(j)}"
      )
    }
    val torqueFormats = joints.map { j =>
      val f = outputFormats(j)
      // Strictly above T_M and the last bin's lower edge: MonitorParams compares them with the format's maximum.
      val needed = Seq(momentary(j), (bins(j) - 1) * widths(j)).map(x =>
        FixedFormat.forRange(x + f.lsb, f.fracBits).intBits
      )
      val widened = FixedFormat((f.intBits +: needed).max, f.fracBits)
      require(
        widened.width <= maxTorqueWidth,
        s"monitor.momentary-peak (${momentary(j)} N·m) or the histogram's span for joint ${names(j)} needs a ${widened.width}-bit torque code " +
          s"(at most $maxTorqueWidth with ${f.fracBits} fraction bits)"
      )
      widened
    }
    // A width of at least one LSB keeps the bin edges (ceil(k w 2^frac)) on distinct codes.
    MonitorParams(
      jointNames = names.map(identifier),
      torqueFormats = torqueFormats,
      velocityFormats = arm.numerics.velocityFormats,
      repeatedPeakNm = repeated,
      momentaryPeakNm = momentary,
      lifeExponents = perJoint(arm, s.exponent, "exponent"),
      gearRatios = perJoint(arm, s.gearRatio, "gear-ratio"),
      histogramBins = bins,
      histogramBinWidthNm = widths,
      samplePeriodS = s.samplePeriodS
    )
  }

  /** Torque range / bins, rounded up to three significant digits, at least one LSB. */
  def autoBinWidth(rangeNm: Double, bins: Int, lsb: Double): Double = {
    val w = rangeNm / bins
    if (w <= lsb) lsb
    else {
      val scale = BigDecimal(10).pow(2 - math.floor(math.log10(w)).toInt)
      ((BigDecimal(w) * scale).setScale(0, BigDecimal.RoundingMode.CEILING) / scale).toDouble
    }
  }

  /**
   * The catalogue rating per joint for the consumed-life figure (None everywhere without
   * `monitor.rated-torque`).
   */
  def rated(arm: ArmParams, s: MonitorSettings): IndexedSeq[Option[RatedReducer]] =
    if (s.ratedTorqueNm.isEmpty) IndexedSeq.fill(arm.chain.size)(None)
    else
      perJoint(arm, s.ratedTorqueNm, "rated-torque").map(t =>
        Some(RatedReducer(t, s.ratedInputSpeedRpm, s.ratedLifeHours))
      )
}
