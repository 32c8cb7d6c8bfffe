package reducerload.arm

import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.compiler.Compiler
import reducerload.dynamics.{RandomChains, Rnea}
import reducerload.graph.{SampleCodes, ScheduleRequest, Storage}
import reducerload.sim.{ArmDriver, Cycle, Stream}
import reducerload.testutil.{ArmGolden, Seeds, SimBackend}

import scala.collection.mutable.ArrayBuffer
import scala.util.Random
import reducerload.testutil.SimBackend.multiplierImpl // the JVM simulator builds the multipliers' Chisel twin

/**
 * One simulation per design: golden samples back to back (one per clock), then seeded random samples (some
 * beyond the declared ranges) with bubbles and resets. Checked: bit-exact against the model at exactly the
 * reported latency, and every in-range torque within the derived bound of double-precision RNEA and of the
 * independent golden torques.
 */
class ArmDatapathSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "ArmDatapath"

  /**
   * Every golden trace of `robot` back to back, then seeded random samples; each joint checked against
   * Pinocchio.
   */
  private def runRobot(
      robot: String,
      seed: Long,
      schedule: ScheduleRequest = ScheduleRequest(),
      targetError: Seq[Double] = Nil
  ): Unit = {
    val traces = ArmGolden.of(robot)
    traces.foreach(t =>
      assert(
        t.config == traces.head.config,
        s"${t.name}: another robot or other ranges than ${traces.head.name}"
      )
    )
    // Fitted with its own schedule, as `run emit` does (per-node caps are kept only where that schedule gets cheaper).
    val p = Compiler.arm(traces.head.config.copy(targetError = targetError, schedule = schedule))
    assert(
      p.errorBound <= ArmChecks.target,
      s"$robot: derived bound ${p.errorBound} misses the target ${ArmChecks.target}"
    )
    val rng = new Random(Seeds(s"arm-$robot", seed))
    val random = IndexedSeq.fill(SimBackend.scale(1000)) {
      val (q, qd, qdd) = RandomChains.sample(rng, p.maxVelocity.map(_ * 1.1), p.maxAcceleration.map(_ * 1.1))
      ArmSample(q, qd, qdd)
    }
    val label = (if (p.schedule.clocksPerSample == 1) robot else s"$robot II=${p.schedule.clocksPerSample}") +
      (if (p.banked.isDefined) " memory" else "") +
      (if (targetError.isEmpty) "" else s" target ${targetError.mkString(",")} (F=${p.internalFracBits})")
    ArmChecks.run(
      this,
      label,
      p,
      traces.flatMap(_.samples).toIndexedSeq,
      random,
      rng,
      Seq("pinocchio" -> traces.flatMap(_.torques).toIndexedSeq),
      ArmChecks.target,
      s => Rnea.reference(p.chain, s.q, s.qd, s.qdd)
    )
  }

  it should "compute every torque of the planar arm within 1e-3 N·m of Pinocchio, bit-exact with the model" in {
    runRobot("planar3", 41L)
  }

  it should "compute every torque of the UR5 within 1e-3 N·m of Pinocchio, bit-exact with the model" in {
    runRobot("ur5", 42L)
  }

  it should "compute every torque of the Panda within 1e-3 N·m of Pinocchio, bit-exact with the model" in {
    runRobot("panda", 43L)
  }

  it should "share multipliers and CORDIC units on planar3 (2, 3 and 40 clocks per sample), bit-exact under back-pressure" in {
    runRobot("planar3", 44L, ScheduleRequest(clocksPerSample = Some(2)))
    runRobot("planar3", 45L, ScheduleRequest(clocksPerSample = Some(3), cordicUnits = Some(1)))
    runRobot("planar3", 46L, ScheduleRequest(clocksPerSample = Some(40)))
  }

  it should "fit the UR5 in the 66 multiplier blocks of an EP4CE30, bit-exact under back-pressure" in {
    runRobot("ur5", 47L, ScheduleRequest(clocksPerSample = None, maxMultipliers = Some(66)))
  }

  it should "keep values in block-RAM banks read by address (storage = memory) on planar3 at 6, 8 and 40 clocks per sample (there with 4 adder units, one left idle), bit-exact under back-pressure" in {
    runRobot(
      "planar3",
      51L,
      ScheduleRequest(clocksPerSample = Some(40), storage = Storage.Memory, adderUnits = Some(4))
    )
    runRobot(
      "planar3",
      50L,
      ScheduleRequest(clocksPerSample = Some(8), cordicUnits = Some(1), storage = Storage.Memory)
    )
    runRobot("planar3", 49L, ScheduleRequest(clocksPerSample = Some(6), storage = Storage.Memory))
  }

  it should "fit the UR5 with block-RAM banks at 64 and 88 clocks per sample and a 1e-3 N·m target, bit-exact under back-pressure" in {
    runRobot(
      "ur5",
      52L,
      ScheduleRequest(clocksPerSample = Some(64), storage = Storage.Memory),
      targetError = Seq(1e-3)
    )
    runRobot(
      "ur5",
      56L,
      ScheduleRequest(clocksPerSample = Some(88), storage = Storage.Memory),
      targetError = Seq(1e-3)
    )
  }

  it should "meet a 1e-3 N·m target on the UR5 with the fewest fraction bits, in 66 blocks" in {
    runRobot(
      "ur5",
      48L,
      ScheduleRequest(clocksPerSample = None, maxMultipliers = Some(66)),
      targetError = Seq(1e-3)
    )
  }
}

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
    val stim = (goldenCodes.map(Cycle.Sample(_)) ++ Stream.randomStimulus(
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
          f"[arm] $label ${names(j)}%-22s max |hw - ${p.dynamics.name}| $err%.3e N·m (bound ${p.errorBounds(j)}%.3e)"
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
          f"[arm] $label ${names(j)}%-22s max |hw - $source| $err%.3e N·m (bound ${p.errorBounds(j)}%.3e, target $target%.0e)"
        )
        assert(
          err <= p.errorBounds(j) + 1e-9,
          s"$label ${names(j)}: error vs $source $err above the derived bound ${p.errorBounds(j)}"
        )
        assert(err <= target, s"$label ${names(j)}: error vs $source $err above the target $target N·m")
      }
      println(
        s"[arm] $label: latency $latency cycles, one sample per $period clocks, ${p.schedule.multiplierBlocks} multiplier blocks, " +
          s"${p.graph.counts}, outputs bit-exact with the model over ${entered.size} cycles"
      )
    }
  }
}
