package reducerload.monitor

import reducerload.arm.{ArmModel, ArmParams, ArmSample}
import reducerload.dynamics.Rnea
import reducerload.graph.SampleCodes
import reducerload.robot.RigidBody

/**
 * Derived bounds on |hardware figure - reference figure| for one joint, where the hardware figures come from
 * the monitor fed by the datapath's torque codes and the reference's from double-precision RNEA at the
 * unquantized inputs (both with the same velocity codes and out-of-range flags). Each torque code is within e
 * (the datapath's derived error bound) of the reference torque, so:
 *   - peak |tau|: e;
 *   - T_av, a |qd|-weighted p-norm of |tau| with the same weights: the power table's relative and absolute
 *     bound carried through the damage sum to the registers' T_av ([[MonitorSummary.avgTorqueBound]]) plus e
 *     (Minkowski: | ||a|| - ||b|| | <= max |a - b|);
 *   - damage sum: the table's bound ([[MonitorSummary.damageSumBound]]) plus, per sample,
 * \|qd| dt ((|tau| + e)^p - |tau|^p) at the reference |tau| (convexity: a torque within e of it has a p-th
 * power within that of its p-th power);
 *   - counts: a sample can fall on the other side of a threshold or bin edge only when its reference |tau| is
 *     within e of it, so a count differs by at most the number of such samples (an event count too: one
 *     sample flipping splits or joins at most one run).
 */
final case class SummaryBounds(
    name: String,
    peakAbsNm: Double,
    avgTorqueNm: Option[Double],
    damageSum: Double,
    repeatedPeakSamples: Int,
    momentaryPeakEvents: Int,
    histogram: Seq[Int]
)

/** One trajectory through the bit-accurate model (datapath then monitor) and the double reference. */
final case class TrajectorySummary(
    monitor: MonitorParams,
    hardware: Seq[JointSummary],
    reference: Seq[JointSummary],
    bounds: Seq[SummaryBounds]
) {

  /** Every figure outside its derived bound, as one line each (empty: all within). */
  def violations: Seq[String] = TrajectorySummary.violations(hardware, reference, bounds)

  /** The summary JSON of issue 13: joints, reference, difference and bound. */
  def json: String = MonitorSummary.json(monitor, hardware, Some(reference), Some(bounds))
}

object TrajectorySummary {

  /**
   * The double-precision reference's inputs: exact RNEA torques, the velocity codes the monitor sees, the
   * same flags.
   */
  def referenceValues(
      arm: ArmParams,
      m: MonitorParams,
      samples: Seq[ArmSample],
      fed: Seq[MonitorSampleCodes],
      payloads: Seq[RigidBody] = Nil
  ): Seq[MonitorSampleValues] =
    samples.zip(fed).zip(padded(payloads, samples.size)).map { case ((s, f), carried) =>
      val chain = arm.payload.zip(carried).fold(arm.chain) { case (spec, b) => spec.merged(arm.chain, b) }
      MonitorSampleValues(
        Rnea.reference(chain, s.q, s.qd, s.qdd),
        f.velocity.indices.map(j => m.velocityFormats(j).toDouble(f.velocity(j))),
        f.outOfRange
      )
    }

  /** Each sample's payload (`payloads` per sample, none beyond them: a design without payload gets Nil). */
  private def padded(payloads: Seq[RigidBody], samples: Int): Seq[Option[RigidBody]] =
    payloads.map(Some(_)) ++ Seq.fill(samples - payloads.size)(None)

  /** What the monitor receives for each sample, by the datapath's bit-accurate model. */
  def monitorInputs(arm: ArmParams, codes: Seq[SampleCodes]): Seq[MonitorSampleCodes] = {
    val model = new ArmModel(arm)
    codes.map(c => MonitoredArm.monitorSample(arm, c, model.evaluate(c)))
  }

  /** The bounds of one period (the samples between a clear and a snapshot), per joint. */
  def bounds(
      arm: ArmParams,
      m: MonitorParams,
      snap: MonitorSnapshot,
      ref: Seq[JointSummary],
      values: Seq[MonitorSampleValues]
  ): Seq[SummaryBounds] =
    (0 until m.joints).map { j =>
      val e = arm.errorBounds(j)
      val tau = values.filter(!_.outOfRange(j)).map(v => math.abs(v.torqueNm(j)))
      def near(level: Double) = tau.count(t => math.abs(t - level) <= e)
      val w = m.histogramBinWidthNm(j)
      val bins = m.histogramBins(j)
      val exponent = m.lifeExponents(j)
      val torqueShare = values
        .filter(!_.outOfRange(j))
        .map { v =>
          val t = math.abs(v.torqueNm(j))
          math.abs(v.velocityRadS(j)) * m.samplePeriodS * (math.pow(t + e, exponent) - math.pow(t, exponent))
        }
        .sum
      SummaryBounds(
        name = m.jointNames(j),
        peakAbsNm = e,
        avgTorqueNm = MonitorSummary.avgTorqueBound(m, j, snap.joints(j)).map(_ + e),
        damageSum = MonitorSummary.damageSumBound(
          m,
          j,
          snap.joints(j).damageSum.toDouble * MonitorSummary.damageScale(m, j),
          ref(j).speedSumRad
        ) + torqueShare * (1 + 1e-12),
        repeatedPeakSamples = near(m.repeatedPeakNm(j)),
        momentaryPeakEvents = near(m.momentaryPeakNm(j)),
        histogram = (0 until bins).map(k =>
          (if (k > 0) near(k * w) else 0) + (if (k < bins - 1) near((k + 1) * w) else 0)
        )
      )
    }

  def violations(
      hardware: Seq[JointSummary],
      reference: Seq[JointSummary],
      bounds: Seq[SummaryBounds]
  ): Seq[String] =
    hardware.indices.flatMap { j =>
      val (h, r, b) = (hardware(j), reference(j), bounds(j))
      def close(what: String, a: Option[Double], x: Option[Double], bound: Option[Double]): Option[String] =
        (a, x, bound) match {
          case (Some(u), Some(v), Some(d)) =>
            if (math.abs(u - v) <= d) None else Some(s"${h.name} $what: hardware $u, reference $v, bound $d")
          case (None, None, _) => None
          case _               => Some(s"${h.name} $what: hardware $a, reference $x (one is missing)")
        }
      def count(what: String, u: BigInt, v: BigInt, bound: Int) =
        if ((u - v).abs <= bound) None else Some(s"${h.name} $what: hardware $u, reference $v, bound $bound")
      Seq(
        if (h.samples == r.samples && h.outOfRangeSamples == r.outOfRangeSamples) None
        else
          Some(
            s"${h.name} samples: hardware ${h.samples}/${h.outOfRangeSamples}, reference " +
              s"${r.samples}/${r.outOfRangeSamples}"
          ),
        close("peak_abs_nm", h.peakAbsNm, r.peakAbsNm, Some(b.peakAbsNm)),
        close("avg_torque_nm", h.avgTorqueNm, r.avgTorqueNm, b.avgTorqueNm),
        close(
          "avg_speed_rad_s",
          h.avgSpeedRadS,
          r.avgSpeedRadS,
          r.avgSpeedRadS.map(v => 1e-12 * (1 + math.abs(v)))
        ),
        close("damage_sum", Some(h.damageSum), Some(r.damageSum), Some(b.damageSum)),
        count("repeated_peak_samples", h.repeatedPeakSamples, r.repeatedPeakSamples, b.repeatedPeakSamples),
        count("momentary_peak_events", h.momentaryPeakEvents, r.momentaryPeakEvents, b.momentaryPeakEvents)
      ).flatten ++ h.histogram.indices.flatMap(k =>
        count(s"histogram[$k]", h.histogram(k), r.histogram(k), b.histogram(k))
      )
    }

  /**
   * A whole trajectory, one sample per sample period, from a cleared monitor: the datapath's model feeds the
   * monitor's model (the figures the hardware's registers would hold), and the double reference gets the
   * exact RNEA torques (with `payloads`, one per sample, each sample's payload merged into the last body).
   */
  def of(
      arm: ArmParams,
      m: MonitorParams,
      samples: Seq[ArmSample],
      rated: Seq[Option[RatedReducer]] = Nil,
      payloads: Seq[RigidBody] = Nil
  ): TrajectorySummary = {
    MonitoredArm.check(arm, m)
    val model = new ArmModel(arm)
    val fed = monitorInputs(
      arm,
      samples.zip(padded(payloads, samples.size)).map { case (s, b) =>
        model.encode(s, b.getOrElse(RigidBody.massless))
      }
    )
    val monitorModel = new MonitorModel(m)
    val live = fed.foldLeft(monitorModel.initial)((s, x) => monitorModel.step(s, MonitorCycle(Some(x)))).live
    val snap = MonitorSnapshot(0, live)
    val values = referenceValues(arm, m, samples, fed, payloads)
    val ref = MonitorReference.summarize(m, values, rated)
    TrajectorySummary(m, MonitorSummary.fromSnapshot(m, snap, rated), ref, bounds(arm, m, snap, ref, values))
  }
}
