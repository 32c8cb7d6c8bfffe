package reducerload.monitor

/**
 * Catalogue rating of a reducer for the life formula (docs/equations.md, Harmonic Drive CSD-2A / HFUS-2SH):
 * rated output torque T_N, rated input speed n_N and rated life L_n (L_n 35,000 h, n_N 2,000 rpm for
 * CSF/CSD/HFUC; RV catalogues give their own K and N0, used the same way).
 */
final case class RatedReducer(torqueNm: Double, inputSpeedRpm: Double, lifeHours: Double) {
  require(
    torqueNm > 0 && inputSpeedRpm > 0 && lifeHours > 0,
    s"RatedReducer: torque, input speed and life must be positive, got $torqueNm N·m, " +
      s"$inputSpeedRpm rpm, $lifeHours h"
  )
}

/** One joint's figures, in physical units, from the hardware's registers or from the double reference. */
final case class JointSummary(
    name: String,
    samples: BigInt,
    outOfRangeSamples: BigInt,
    runTimeS: Double,
    peakNm: Option[Double],
    minNm: Option[Double],
    avgTorqueNm: Option[Double],
    avgSpeedRadS: Option[Double],
    repeatedPeakSamples: BigInt,
    momentaryPeakEvents: BigInt,
    lastEventPeakNm: Option[Double],
    lastEventDurationSamples: BigInt,
    lastEventSpeedRadS: Option[Double],
    histogram: Seq[BigInt],
    damageSum: Double,
    speedSumRad: Double,
    lifeHours: Option[Double]
) {

  /** Largest |tau| since clear (None before the first in-range sample). */
  def peakAbsNm: Option[Double] = for (a <- peakNm; b <- minNm) yield math.abs(a).max(math.abs(b))

  /** Fraction of the catalogue life used by the run time (None without a rating or without motion). */
  def consumedLifeFraction: Option[Double] = lifeHours.map(l => runTimeS / 3600.0 / l)
}

/** Figures from the registers, the catalogue life formula and the JSON rendering. */
object MonitorSummary {

  /**
   * L50 = L_n * (n_N / (i * n_av)) * (T_N / T_av)^p, n_av the average output speed in rpm (i n_av is the
   * average input speed). None when the joint never moved (no T_av) or stood still.
   */
  def life(
      p: MonitorParams,
      j: Int,
      avgTorqueNm: Option[Double],
      avgSpeedRadS: Option[Double],
      rated: Option[RatedReducer]
  ): Option[Double] =
    for {
      r <- rated
      tav <- avgTorqueNm if tav > 0
      w <- avgSpeedRadS if w > 0
    } yield {
      val nAvRpm = w * 60.0 / (2 * math.Pi)
      r.lifeHours * (r.inputSpeedRpm / (p.gearRatios(j) * nAvRpm)) * math.pow(
        r.torqueNm / tav,
        p.lifeExponents(j)
      )
    }

  /** Physical scale of one damage-sum code: 2^-valueFracBits x fullScale^p x qd lsb x dt (N·m^p·rad). */
  def damageScale(p: MonitorParams, j: Int): Double =
    math.pow(2.0, -p.powerTables(j).valueFracBits) * math
      .pow(p.torqueFullScaleNm(j), p.lifeExponents(j)) * p.velocityFormats(j).lsb * p.samplePeriodS

  /**
   * x = (sum |qd| u^p) / (sum |qd|) from the registers, exactly then rounded once (None if the joint never
   * moved).
   */
  def normalisedPowerMean(p: MonitorParams, j: Int, s: JointState): Option[Double] =
    if (s.speedSum == 0) None
    else
      Some(
        (BigDecimal(s.damageSum) / (BigDecimal(s.speedSum) * BigDecimal(2).pow(
          p.powerTables(j).valueFracBits
        ))).toDouble
      )

  /** The summary of one snapshot (RTL or model). */
  def fromSnapshot(
      p: MonitorParams,
      snap: MonitorSnapshot,
      rated: Seq[Option[RatedReducer]] = Nil
  ): Seq[JointSummary] =
    (0 until p.joints).map { j =>
      val s = snap.joints(j)
      val (tf, vf) = (p.torqueFormats(j), p.velocityFormats(j))
      val any = s.samples > 0
      val inEvents = s.momentaryPeakEvents > 0 || s.inEvent
      val avgTorque =
        normalisedPowerMean(p, j, s).map(x => p.torqueFullScaleNm(j) * math.pow(x, 1.0 / p.lifeExponents(j)))
      val avgSpeed = if (any) Some(s.speedSum.toDouble * vf.lsb / s.samples.toDouble) else None
      JointSummary(
        name = p.jointNames(j),
        samples = s.samples,
        outOfRangeSamples = s.outOfRangeSamples,
        runTimeS = s.samples.toDouble * p.samplePeriodS,
        peakNm = if (any) Some(tf.toDouble(s.peakTorque)) else None,
        minNm = if (any) Some(tf.toDouble(s.minTorque)) else None,
        avgTorqueNm = avgTorque,
        avgSpeedRadS = avgSpeed,
        repeatedPeakSamples = s.repeatedPeakSamples,
        momentaryPeakEvents = s.momentaryPeakEvents,
        lastEventPeakNm = if (inEvents) Some(s.lastEventPeak.toDouble * tf.lsb) else None,
        lastEventDurationSamples = s.lastEventDuration,
        lastEventSpeedRadS = if (inEvents) Some(s.lastEventSpeed.toDouble * vf.lsb) else None,
        histogram = s.histogram,
        damageSum = s.damageSum.toDouble * damageScale(p, j),
        speedSumRad = s.speedSum.toDouble * vf.lsb * p.samplePeriodS,
        lifeHours = life(p, j, avgTorque, avgSpeed, rated.lift(j).flatten)
      )
    }

  /**
   * Derived bound on |damage sum (registers) - sum |qd| |tau|^p dt| over the torques the monitor received
   * (the table's share of the error). Every sample's power is within rel x |tau|^p + abs (abs = the table's
   * absolute bound x fullScale^p), weighted by w = |qd| dt: with X the exact sum, |D - X| <= rel X + abs S1,
   * and X <= (D + abs S1) / (1 - rel), so |D - X| <= (rel D + abs S1) / (1 - rel). From the registers alone
   * (D, S1 = sum |qd| dt).
   */
  def damageSumBound(p: MonitorParams, j: Int, damageSum: Double, speedSumRad: Double): Double = {
    val (rel, abs) = (
      p.powerRelativeBound(j),
      p.powerAbsoluteBound(j) * math.pow(p.torqueFullScaleNm(j), p.lifeExponents(j))
    )
    (rel * math.abs(damageSum) + abs * speedSumRad) / (1 - rel) * (1 + 1e-12)
  }

  /**
   * Derived bound on |T_av (registers) - T_av of the torques the monitor received|. In u = |tau| / full
   * scale: the registers' mean x = D / S1 and the exact mean y = sum w u^p / S1 satisfy |x - y| <= rel y +
   * abs (each sample's power is), so y lies in [(x - abs) / (1 + rel), (x + abs) / (1 - rel)]; T_av =
   * fullScale x^(1/p) and the exact one fullScale y^(1/p): the bound is the larger distance to the ends of
   * that interval (plus the double evaluation's rounding).
   */
  def avgTorqueBound(p: MonitorParams, j: Int, s: JointState): Option[Double] =
    normalisedPowerMean(p, j, s).map { x =>
      val (rel, abs, q) = (p.powerRelativeBound(j), p.powerAbsoluteBound(j), 1.0 / p.lifeExponents(j))
      val (lo, hi) = (((x - abs) / (1 + rel)).max(0.0), (x + abs) / (1 - rel))
      val t = math.pow(x, q)
      p.torqueFullScaleNm(j) * ((t - math.pow(lo, q)).max(math.pow(hi, q) - t) + 1e-12 * t) * (1 + 1e-12)
    }

  // ---- JSON ----
  private def str(s: String): String =
    "\"" + s.flatMap {
      case '"'          => "\\\""
      case '\\'         => "\\\\"
      case c if c < ' ' => f"\\u${c.toInt}%04x"
      case c            => c.toString
    } + "\""
  private def num(x: Double): String = if (x.isNaN || x.isInfinite) "null" else x.toString
  private def opt(x: Option[Double]): String = x.fold("null")(num)
  private def obj(fields: Seq[(String, String)], indent: String): String =
    fields.map { case (k, v) => s"$indent  ${str(k)}: $v" }.mkString("{\n", ",\n", s"\n$indent}")

  /** One joint as a JSON object (field names as in issue 13). */
  def jointJson(p: MonitorParams, s: JointSummary, indent: String = "    "): String = {
    val j = p.jointNames.indexOf(s.name)
    obj(
      Seq(
        "name" -> str(s.name),
        "samples" -> s.samples.toString,
        "out_of_range_samples" -> s.outOfRangeSamples.toString,
        "run_time_s" -> num(s.runTimeS),
        "peak_abs_nm" -> opt(s.peakAbsNm),
        "peak_nm" -> opt(s.peakNm),
        "min_nm" -> opt(s.minNm),
        "avg_torque_nm" -> opt(s.avgTorqueNm),
        "avg_speed_rad_s" -> opt(s.avgSpeedRadS),
        "repeated_peak_samples" -> s.repeatedPeakSamples.toString,
        "momentary_peak_events" -> s.momentaryPeakEvents.toString,
        "last_event_peak_nm" -> opt(s.lastEventPeakNm),
        "last_event_duration_samples" -> s.lastEventDurationSamples.toString,
        "last_event_speed_rad_s" -> opt(s.lastEventSpeedRadS),
        "histogram" -> s.histogram.mkString("[", ", ", "]"),
        "histogram_bin_width_nm" -> (if (j >= 0) num(p.histogramBinWidthNm(j)) else "null"),
        "damage_sum_nm_p_rad" -> num(s.damageSum),
        "speed_sum_rad" -> num(s.speedSumRad),
        "life_exponent" -> (if (j >= 0) num(p.lifeExponents(j)) else "null"),
        "life_hours" -> opt(s.lifeHours),
        "consumed_life_fraction" -> opt(s.consumedLifeFraction)
      ),
      indent
    )
  }

  /**
   * A trajectory (one sample per sample period, from a cleared monitor) through the arm datapath's and the
   * monitor's bit-accurate models, and through the double reference (exact RNEA torques): both summaries and
   * the derived bounds on their differences. `.json` renders the summary file.
   */
  def fromTrajectory(
      arm: reducerload.arm.ArmParams,
      p: MonitorParams,
      samples: Seq[reducerload.arm.ArmSample],
      rated: Seq[Option[RatedReducer]] = Nil,
      payloads: Seq[reducerload.robot.RigidBody] = Nil
  ): TrajectorySummary = TrajectorySummary.of(arm, p, samples, rated, payloads)

  /**
   * `{"joints": [...]}`, with the reference's figures, the differences and their derived bounds when given.
   */
  def json(
      p: MonitorParams,
      hardware: Seq[JointSummary],
      reference: Option[Seq[JointSummary]] = None,
      bounds: Option[Seq[SummaryBounds]] = None
  ): String = {
    def list(xs: Seq[JointSummary]) = xs.map(s => "    " + jointJson(p, s)).mkString("[\n", ",\n", "\n  ]")
    val diffs = reference.map { ref =>
      hardware
        .zip(ref)
        .map { case (h, r) =>
          def d(a: Option[Double], b: Option[Double]) = opt(for (x <- a; y <- b) yield x - y)
          "    " + obj(
            Seq(
              "name" -> str(h.name),
              "avg_torque_nm" -> d(h.avgTorqueNm, r.avgTorqueNm),
              "avg_speed_rad_s" -> d(h.avgSpeedRadS, r.avgSpeedRadS),
              "peak_abs_nm" -> d(h.peakAbsNm, r.peakAbsNm),
              "damage_sum_nm_p_rad" -> num(h.damageSum - r.damageSum),
              "repeated_peak_samples" -> (h.repeatedPeakSamples - r.repeatedPeakSamples).toString,
              "momentary_peak_events" -> (h.momentaryPeakEvents - r.momentaryPeakEvents).toString,
              "histogram_equal" -> (h.histogram == r.histogram).toString
            ),
            "    "
          )
        }
        .mkString("[\n", ",\n", "\n  ]")
    }
    val bound = bounds.map(_.map { b =>
      "    " + obj(
        Seq(
          "name" -> str(b.name),
          "avg_torque_nm" -> opt(b.avgTorqueNm),
          "peak_abs_nm" -> num(b.peakAbsNm),
          "damage_sum_nm_p_rad" -> num(b.damageSum),
          "repeated_peak_samples" -> b.repeatedPeakSamples.toString,
          "momentary_peak_events" -> b.momentaryPeakEvents.toString,
          "histogram" -> b.histogram.mkString("[", ", ", "]")
        ),
        "    "
      )
    }.mkString("[\n", ",\n", "\n  ]"))
    val fields =
      Seq("sample_period_s" -> num(p.samplePeriodS), "joints" -> list(hardware)) ++ reference.map(r =>
        "reference" -> list(r)
      ) ++
        diffs.map("difference" -> _) ++ bound.map("bound" -> _)
    obj(fields, "") + "\n"
  }
}
