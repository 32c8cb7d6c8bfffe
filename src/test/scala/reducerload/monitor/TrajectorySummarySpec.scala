package reducerload.monitor

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.arm.ArmParams
import reducerload.config.{DatapathParams, MonitorSettings}
import reducerload.testutil.ArmGolden

/**
 * MonitorSummary.fromTrajectory on a golden trajectory: the model's figures within the derived bounds of the
 * double reference.
 */
class TrajectorySummarySpec extends AnyFlatSpec {
  behavior of "MonitorSummary.fromTrajectory"

  private val trace = ArmGolden.load("planar3_multiturn.csv")
  // 22 internal fraction bits: the datapath this test was written against (ArmParams' default then).
  private val arm = ArmParams(
    trace.chain,
    trace.config.robot.maxVelocity,
    trace.config.robot.maxAcceleration,
    datapath = DatapathParams(internalFracBits = 22)
  )

  /**
   * The trajectory is sampled every 10 ms; limits where it crosses them (its peaks are about 104, 46, 30
   * N·m).
   */
  private val settings = MonitorSettings(
    enabled = true,
    repeatedPeakNm = Seq(80.0, 30.0, 20.0),
    momentaryPeakNm = Seq(100.0, 40.0, 28.0),
    gearRatio = Seq(120.0, 100.0, 80.0),
    samplePeriodS = 0.01,
    histogramBins = Seq(10),
    ratedTorqueNm = Seq(150.0, 80.0, 40.0)
  )

  it should "summarize planar3_multiturn within the derived bounds of the " +
    "double reference, with consumed life" in {
      val m = MonitorConfig(arm, settings)
      val summary = MonitorSummary.fromTrajectory(arm, m, trace.samples, MonitorConfig.rated(arm, settings))
      println(
        s"[summary] ${trace.name}, ${trace.samples.size} samples at ${m.samplePeriodS} s:\n${summary.json}"
      )
      assert(summary.violations.isEmpty, summary.violations.mkString("\n"))
      summary.hardware.zip(summary.reference).foreach { case (h, r) =>
        assert(
          h.samples == trace.samples.size && h.outOfRangeSamples == 0,
          s"${h.name}: every golden sample is in range"
        )
        assert(
          h.avgTorqueNm.isDefined && h.lifeHours.isDefined && h.consumedLifeFraction.exists(_ > 0),
          s"${h.name}: T_av and life"
        )
        assert(h.histogram.sum == h.samples && r.histogram.sum == r.samples)
      }
      assert(
        summary.hardware.exists(_.repeatedPeakSamples > 0) && summary.hardware.exists(
          _.momentaryPeakEvents > 0
        ),
        "the limits were chosen so the trajectory crosses them"
      )
      val json = summary.json
      Seq(
        "\"joints\"",
        "\"reference\"",
        "\"difference\"",
        "\"bound\"",
        "\"peak_abs_nm\"",
        "\"avg_torque_nm\"",
        "\"avg_speed_rad_s\"",
        "\"repeated_peak_samples\"",
        "\"momentary_peak_events\"",
        "\"histogram\"",
        "\"consumed_life_fraction\""
      ).foreach(k => assert(json.contains(k), s"summary JSON lacks $k"))
      assert(json.count(_ == '{') == json.count(_ == '}') && json.count(_ == '[') == json.count(_ == ']'))
    }

  it should "give null T_av for a joint that never moved" in {
    val still = trace.samples.take(50).map(s => s.copy(qd = s.qd.map(_ => 0.0)))
    val summary = MonitorSummary.fromTrajectory(arm, MonitorConfig(arm, settings), still)
    assert(summary.hardware.forall(_.avgTorqueNm.isEmpty) && summary.reference.forall(_.avgTorqueNm.isEmpty))
    assert(summary.json.contains("\"avg_torque_nm\": null") && summary.violations.isEmpty)
  }
}
