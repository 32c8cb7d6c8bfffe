package reducerload.monitor

import reducerload.testutil.CompiledParams
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.fixedpoint.Rounding
import reducerload.config.LoadParams
import reducerload.testutil.{Golden, Seeds}

import scala.util.Random

/** The model against the double reference on the golden trajectories and random streams; life and JSON. */
class MonitorModelSpec extends AnyFlatSpec {
  behavior of "MonitorModel and MonitorSummary"

  /**
   * One joint fed like the datapath: the golden tau3 in the load output format, d3 in the velocity format.
   */
  private def goldenParams(exponent: Double): MonitorParams = {
    val lp = LoadParams.default
    MonitorParams(
      Seq("joint3"),
      Seq(lp.arm.analysis.outputPortFormat),
      Seq(lp.arm.numerics.velocityFormats(2)),
      Seq(60.0),
      Seq(90.0),
      Seq(exponent),
      Seq(101.0),
      Seq(12),
      Seq(10.0),
      samplePeriodS = 5e-3
    )
  }

  private def compare(p: MonitorParams, samples: Seq[MonitorSampleCodes], label: String): Unit = {
    val model = new MonitorModel(p)
    val end =
      model.run((samples.map(s => MonitorCycle(Some(s))) :+ MonitorCycle(None, snapshot = true)).iterator)
    val hw = MonitorSummary.fromSnapshot(p, end.shadow)
    val ref = MonitorReference.summarize(p, samples.map(MonitorReference.values(p, _)))
    (0 until p.joints).foreach { j =>
      val (h, r) = (hw(j), ref(j))
      assert(h.histogram == r.histogram, s"$label ${h.name}: histogram ${h.histogram} vs ${r.histogram}")
      assert(
        h.repeatedPeakSamples == r.repeatedPeakSamples && h.momentaryPeakEvents == r.momentaryPeakEvents,
        s"$label ${h.name}: counts"
      )
      assert(
        h.peakAbsNm == r.peakAbsNm && h.lastEventPeakNm == r.lastEventPeakNm &&
          h.lastEventDurationSamples == r.lastEventDurationSamples
      )
      val damageBound = MonitorSummary.damageSumBound(p, j, h.damageSum, r.speedSumRad)
      val tavBound = MonitorSummary.avgTorqueBound(p, j, end.shadow.joints(j)).get
      val (dErr, tErr) =
        (math.abs(h.damageSum - r.damageSum), math.abs(h.avgTorqueNm.get - r.avgTorqueNm.get))
      println(
        f"[monitor] $label ${h.name} p=${p.lifeExponents(j)}%.3f: T_av ${h.avgTorqueNm.get}%.6f N·m " +
          f"(ref ${r.avgTorqueNm.get}%.6f, error $tErr%.2e, bound $tavBound%.2e), damage error " +
          f"${dErr / r.damageSum}%.2e relative (bound ${damageBound / r.damageSum}%.2e), peak " +
          f"${h.peakAbsNm.get}%.3f N·m, ${h.repeatedPeakSamples} > T_R, ${h.momentaryPeakEvents} events"
      )
      assert(dErr <= damageBound && tErr <= tavBound, s"$label ${h.name}: beyond the derived bound")
      assert(math.abs(h.avgSpeedRadS.get - r.avgSpeedRadS.get) <= 1e-12 * (1 + r.avgSpeedRadS.get))
    }
  }

  it should "agree with the double reference on every golden trajectory within the " +
    "derived bound (p = 3 and 10/3)" in {
      for (exponent <- Seq(3.0, 10.0 / 3.0); t <- Golden.all) {
        val p = goldenParams(exponent)
        val samples = t.samples.indices.map { i =>
          MonitorSampleCodes(
            IndexedSeq(p.torqueFormats(0).quantize(t.exact(i), Rounding.HalfUp)),
            IndexedSeq(p.velocityFormats(0).quantize(t.samples(i).qd(2), Rounding.HalfUp)),
            IndexedSeq(false)
          )
        }
        compare(p, samples, t.name)
      }
    }

  it should "agree with the double reference on seeded random dwell streams (p = 3, 10/3, 1.5)" in {
    val p = MonitorStimulus.threeJoints
    compare(p, MonitorStimulus.samples(p, 50000, new Random(Seeds("monitor-model-random", 1304L))), "random")
  }

  it should "give the catalogue life: rated torque and input speed give the rated " +
    "life; p-th power law in torque" in {
      val p = MonitorStimulus.threeJoints
      val rated = RatedReducer(torqueNm = 50.0, inputSpeedRpm = 2000.0, lifeHours = 35000.0)
      // Output speed such that i * n_av = n_N: 2000 rpm / 100 = 20 rpm.
      val w = 20.0 * 2 * math.Pi / 60.0
      assert(math.abs(MonitorSummary.life(p, 0, Some(50.0), Some(w), Some(rated)).get - 35000.0) < 1e-6)
      assert(math.abs(MonitorSummary.life(p, 0, Some(100.0), Some(w), Some(rated)).get - 35000.0 / 8) < 1e-6)
      assert(math.abs(MonitorSummary.life(p, 0, Some(50.0), Some(w * 2), Some(rated)).get - 17500.0) < 1e-6)
      assert(
        MonitorSummary.life(p, 0, None, Some(w), Some(rated)).isEmpty && MonitorSummary
          .life(p, 0, Some(50.0), Some(w), None)
          .isEmpty
      )
    }

  it should "render the summary as JSON with null for a joint that never moved" in {
    val p = MonitorStimulus.threeJoints
    val still = MonitorSampleCodes(
      IndexedSeq(BigInt(1000), BigInt(-5), BigInt(0)),
      IndexedSeq(BigInt(0), BigInt(0), BigInt(0)),
      IndexedSeq(false, false, true)
    )
    val m = new MonitorModel(p)
    val end = m.run(Iterator(MonitorCycle(Some(still)), MonitorCycle(None, snapshot = true)))
    val hw = MonitorSummary.fromSnapshot(p, end.shadow, Seq(Some(RatedReducer(50, 2000, 35000)), None, None))
    val ref = MonitorReference.summarize(p, Seq(MonitorReference.values(p, still)))
    val json = MonitorSummary.json(p, hw, Some(ref))
    println(json.linesIterator.take(26).mkString("\n"))
    assert(
      json.contains("\"avg_torque_nm\": null") && json.contains("\"peak_abs_nm\": null") && json.contains(
        "\"out_of_range_samples\": 1"
      )
    )
    assert(
      json.contains("\"name\": \"base\"") && json.contains("\"difference\"") && json.contains(
        "\"histogram\": [1, 0,"
      )
    )
    assert(json.count(_ == '{') == json.count(_ == '}') && json.count(_ == '[') == json.count(_ == ']'))
  }
}
