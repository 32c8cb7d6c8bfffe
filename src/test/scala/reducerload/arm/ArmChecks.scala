package reducerload.arm

import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.graph.SampleCodes
import reducerload.sim.rtl.{ArmDriver, Cycle, Stream}
import reducerload.testutil.SimBackend

import scala.collection.mutable.ArrayBuffer
import scala.util.Random
import reducerload.testutil.SimBackend.multiplierImpl // the JVM simulator builds the multipliers' Chisel twin

/** Test logic, apart from the simulator calls (those are in ArmDriver). */
object ArmChecks {

  /** The fixed accuracy target of the arm presets, N·m, beside each joint's derived bound. */
  val target: Double = 1e-3

  /**
   * Runs golden samples then random ones through the RTL, each offered until the design takes it
   * (back-pressure); checks bits against the model at the reported latency after the cycle each sample
   * entered, the interval between samples, and every output torque against `reference` (the same dynamics in
   * doubles) within its derived bound, and against each independent golden set (`goldenTorques`: name,
   * torques per golden sample and output) within its bound and `target` N·m.
   */
  def run(
      spec: AnyFlatSpec with ChiselScalatestTester,
      label: String,
      p: ArmParams,
      golden: IndexedSeq[ArmSample],
      random: IndexedSeq[ArmSample],
      rng: Random,
      goldenTorques: Seq[(String, IndexedSeq[IndexedSeq[Double]])],
      target: Double,
      reference: ArmSample => IndexedSeq[Double]
  ): Unit = {
    import spec._
    val model = new ArmModel(p)
    val latency = p.latency
    val goldenCodes = golden.map(model.encode)
    // Bubbles between the parts: a reset early in the random part must not flush the last golden samples
    // (it did on the JVM simulator's shorter streams: planar3's golden sample 2895 had no output).
    val stim =
      (goldenCodes.map(Cycle.Sample(_)) ++ IndexedSeq.fill(latency)(Cycle.Bubble) ++ Stream.randomStimulus(
        rng,
        random.map(model.encode),
        bubble = 0.2,
        resets = 2
      )) ++
        IndexedSeq.fill(latency + 1)(Cycle.Bubble)
    test(new ArmDatapath(p)).withAnnotations(SimBackend.annotations) { dut =>
      val observed = ArrayBuffer.empty[Option[ArmOutputCodes]]
      val entered = ArrayBuffer.empty[Cycle[SampleCodes]]
      ArmDriver.run(
        dut,
        stim.iterator,
        (_, out) => observed += out,
        (_, c) => entered += c,
        holdUntilReady = true
      )
      val expected = Stream.expected[SampleCodes](entered.toIndexedSeq, latency).map(_.map(model.evaluate))
      val bad = Stream.mismatches[ArmOutputCodes, ArmOutputCodes](expected, observed.toIndexedSeq, _ == _)
      assert(bad.isEmpty, bad.mkString(s"$label: RTL differs from the model:\n", "\n", ""))
      // Samples offered back to back enter exactly every clocksPerSample clocks, never closer.
      val takenAt = entered.indices.filter(t => entered(t).isInstanceOf[Cycle.Sample[_]])
      val gaps = takenAt.zip(takenAt.drop(1)).map { case (a, b) => b - a }
      val period = p.schedule.clocksPerSample
      assert(
        gaps.take(golden.size - 1).forall(_ == period),
        s"$label: golden samples entered ${gaps.take(golden.size - 1).distinct} clocks apart, not $period"
      )
      val betweenResets = takenAt.zip(takenAt.drop(1)).filterNot { case (a, b) =>
        (a until b).exists(entered(_) == Cycle.Reset)
      }
      assert(
        betweenResets.forall { case (a, b) => b - a >= period },
        s"$label: two samples entered less than $period clocks apart"
      )
      val hw = golden.indices.map(k =>
        observed(takenAt(k) + latency).getOrElse(fail(s"$label: golden sample $k produced no output"))
      )
      assert(
        hw.forall(!_.outOfRange.exists(identity)),
        s"$label: an in-range golden sample raised outOfRange"
      )
      val tau = hw.map(model.torques)
      val ref = golden.map(reference)
      val names = p.graph.outputs.map(_.name)
      names.indices.foreach { j =>
        val err = tau.zip(ref).map { case (h, r) => math.abs(h(j) - r(j)) }.max
        println(
          f"[arm] $label ${names(j)}%-22s max |hw - ${p.dynamics.name}| $err%.3e N·m " +
            f"(bound ${p.errorBounds(j)}%.3e)"
        )
        assert(
          err <= p.errorBounds(j),
          s"$label ${names(j)}: error $err above the derived bound ${p.errorBounds(j)}"
        )
      }
      for ((source, torques) <- goldenTorques; j <- names.indices) {
        assert(
          torques.size == golden.size,
          s"$label: ${torques.size} $source torques for ${golden.size} golden samples"
        )
        val err = tau.zip(torques).map { case (h, r) => math.abs(h(j) - r(j)) }.max
        println(
          f"[arm] $label ${names(j)}%-22s max |hw - $source| $err%.3e N·m (bound " +
            f"${p.errorBounds(j)}%.3e, target $target%.0e)"
        )
        assert(
          err <= p.errorBounds(j) + 1e-9,
          s"$label ${names(j)}: error vs $source $err above the derived bound ${p.errorBounds(j)}"
        )
        assert(err <= target, s"$label ${names(j)}: error vs $source $err above the target $target N·m")
      }
      println(
        s"[arm] $label: latency $latency cycles, one sample per $period clocks, " +
          s"${p.schedule.multiplierBlocks} multiplier blocks, ${p.graph.counts}, outputs bit-exact with " +
          s"the model over ${entered.size} cycles"
      )
    }
  }
}
