package reducerload.arm

import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.compiler.Compiler
import reducerload.cordic.CordicParams
import reducerload.dynamics.{RandomChains, Rnea}
import reducerload.graph.{ListOrder, Reassociation, ScheduleRequest, Scheduler, Storage}
import reducerload.testutil.{ArmGolden, Seeds, SimBackend}

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
      targetError: Seq[Double] = Nil,
      reassociate: Reassociation = Reassociation.Off,
      routed: Boolean = false,
      memoryDelayMinCycles: Option[Int] = None,
      cordic: CordicParams => CordicParams = identity,
      composeParallelAxes: Boolean = false
  ): Unit = {
    val traces = ArmGolden.of(robot)
    traces.foreach(t =>
      assert(
        t.config == traces.head.config,
        s"${t.name}: another robot or other ranges than ${traces.head.name}"
      )
    )
    // Fitted with its own schedule, as `run emit` does (per-node caps are kept only where that schedule gets
    // cheaper).
    val config = traces.head.config
    val p = Compiler.arm(
      config.copy(
        targetError = targetError,
        schedule = schedule,
        cordic = cordic(config.cordic),
        datapath = config.datapath.copy(
          reassociate = reassociate,
          registeredRoutes = Some(routed),
          memoryDelayMinCycles = memoryDelayMinCycles.getOrElse(config.datapath.memoryDelayMinCycles),
          composeParallelAxes = composeParallelAxes
        )
      )
    )
    assert(
      p.errorBound <= ArmChecks.target,
      s"$robot: derived bound ${p.errorBound} misses the target ${ArmChecks.target}"
    )
    assert(
      !schedule.shareRegisters || p.schedule.sharedRegisters.nonEmpty,
      s"$robot: schedule.share-registers asked, no register shared"
    )
    assert(
      !schedule.productMemories || p.schedule.productMemories.nonEmpty,
      s"$robot: schedule.product-memories asked, no product memory"
    )
    assert(
      !schedule.sinCosMemories || p.schedule.sinCosMemories.nonEmpty,
      s"$robot: schedule.sin-cos-memories asked, no sin/cos memory"
    )
    assert(
      !schedule.readerCopies || p.schedule.readerCopies.nonEmpty,
      s"$robot: schedule.reader-copies asked, no reader's copy"
    )
    assert(
      schedule.forwardSlack.isEmpty || p.graph.ids.exists(p.schedule.forwarded),
      s"$robot: schedule.forward-slack asked, no product forwarded"
    )
    assert(
      schedule.accumulateSlack.isEmpty || p.schedule.accumulations.nonEmpty,
      s"$robot: schedule.accumulate-slack asked, no tree accumulated"
    )
    val rng = new Random(Seeds(s"arm-$robot", seed))
    val random = IndexedSeq.fill(SimBackend.scale(1000)) {
      val (q, qd, qdd) = RandomChains.sample(rng, p.maxVelocity.map(_ * 1.1), p.maxAcceleration.map(_ * 1.1))
      ArmSample(q, qd, qdd)
    }
    val label = (if (p.schedule.clocksPerSample == 1) robot else s"$robot II=${p.schedule.clocksPerSample}") +
      (if (p.banked.isDefined) " memory" else "") +
      (if (targetError.isEmpty) "" else s" target ${targetError.mkString(",")} (F=${p.internalFracBits})") +
      (if (reassociate == Reassociation.Off) "" else s" reassociate $reassociate") +
      (if (routed) " registered routes" else "") +
      (if (composeParallelAxes) " parallel axes composed" else "") +
      (if (p.schedule.sharedRegisters.isEmpty) ""
       else s" ${p.schedule.sharedRegisters.size} shared registers") +
      (if (p.schedule.readerCopies.isEmpty) ""
       else s" ${p.schedule.readerCopyCount} copies") +
      (if (p.schedule.accumulations.isEmpty) ""
       else s" ${p.schedule.accumulations.size} trees accumulated") +
      (if (p.schedule.productMemories.isEmpty) ""
       else s" ${p.schedule.productMemoryOf.size} products in ${p.schedule.productMemories.size} memories") +
      (if (p.schedule.sinCosMemories.isEmpty) ""
       else
         s" ${p.schedule.sinCosMemoryOf.size} sin/cos reads from ${p.schedule.sinCosMemories.size} memories")
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

  it should "build a joint whose torque is identically zero (a constant output, issue 30 item 1), " +
    "bit-exact with the model" in {
      val file = java.nio.file.Paths.get(getClass.getResource("/urdf/massless_last.urdf").toURI).toString
      val robot = reducerload.robot.RobotParams(
        source = file,
        maxVelocity = Nil,
        maxAcceleration = Seq(10.0),
        allowMassless = true
      )
      val p = Compiler.arm(reducerload.config.LoadParams.arm.copy(robot = robot))
      assert(p.graph.outputs.exists(o => p.graph(o.node).isInstanceOf[reducerload.graph.Op.Const]))
      val rng = new Random(Seeds("arm-massless-last", 57L))
      def samples(k: Int) = IndexedSeq.fill(k) {
        val (q, qd, qdd) =
          RandomChains.sample(rng, p.maxVelocity.map(_ * 1.1), p.maxAcceleration.map(_ * 1.1))
        ArmSample(q, qd, qdd)
      }
      val golden = IndexedSeq.fill(20) {
        val (q, qd, qdd) = RandomChains.sample(rng, p.maxVelocity, p.maxAcceleration)
        ArmSample(q, qd, qdd)
      }
      ArmChecks.run(
        this,
        "massless last joint",
        p,
        golden,
        samples(SimBackend.scale(200)),
        rng,
        Nil,
        ArmChecks.target,
        s => Rnea.reference(p.chain, s.q, s.qd, s.qdd)
      )
    }

  it should "compute every torque of the planar arm within 1e-3 N·m of " +
    "Pinocchio, bit-exact with the model" in {
      runRobot("planar3", 41L)
    }

  it should "compute every torque of the UR5 within 1e-3 N·m of Pinocchio, bit-exact with the model" in {
    runRobot("ur5", 42L)
  }

  it should "compute every torque of the Panda within 1e-3 N·m of Pinocchio, bit-exact with the model" in {
    runRobot("panda", 43L)
  }

  it should "share units on planar3 at 2, 3, 4 and 40 clocks per sample (registered routes at 3 and 40, " +
    "readers' copies at 4, shared registers or product memories at 40, accumulators at 3 and 40, sin/cos " +
    "memories at 40), " +
    "bit-exact under back-pressure" in {
      runRobot("planar3", 44L, ScheduleRequest(clocksPerSample = Some(2)))
      runRobot(
        "planar3",
        45L,
        ScheduleRequest(clocksPerSample = Some(3), cordicUnits = Some(1), accumulateSlack = Some(2))
      )
      runRobot("planar3", 46L, ScheduleRequest(clocksPerSample = Some(40), productMemories = true))
      runRobot(
        "planar3",
        59L,
        ScheduleRequest(clocksPerSample = Some(3), cordicUnits = Some(1)),
        routed = true
      )
      runRobot(
        "planar3",
        68L,
        ScheduleRequest(clocksPerSample = Some(4), cordicUnits = Some(1), readerCopies = true),
        routed = true
      )
      runRobot(
        "planar3",
        60L,
        ScheduleRequest(
          clocksPerSample = Some(40),
          shareRegisters = true,
          accumulateSlack = Some(8),
          sinCosMemories = true
        ),
        routed = true
      )
    }

  // The sweep's latency66 recipe: 3 clocks per sample, registered routes, the solver's schedule, slack-0
  // products forwarded, a CORDIC of two micro-rotations per stage from a 2^11 table.
  it should "push critical constants into rotations on planar3, bit-exact under back-pressure" in {
    runRobot(
      "planar3",
      67L,
      ScheduleRequest(
        clocksPerSample = Some(3),
        cordicUnits = Some(1),
        scheduler = Scheduler.CpSat,
        forwardSlack = Some(0)
      ),
      reassociate = Reassociation.SumsAndProducts,
      routed = true,
      cordic = _.copy(tableBits = 11, iterationsPerStage = 2)
    )
  }

  it should "fit the UR5 in the 66 multiplier blocks of an EP4CE30, bit-exact under back-pressure" in {
    runRobot("ur5", 47L, ScheduleRequest(clocksPerSample = None, maxMultipliers = Some(66)))
  }

  it should "keep values in block-RAM banks read by address (storage = memory) on planar3 at 6, 8 (registered " +
    "routes, parallel axes composed) and 40 clocks per sample (there with 4 adder units, one left " +
    "idle), bit-exact under back-pressure" in {
      runRobot(
        "planar3",
        51L,
        ScheduleRequest(clocksPerSample = Some(40), storage = Some(Storage.Memory), adderUnits = Some(4))
      )
      runRobot(
        "planar3",
        50L,
        ScheduleRequest(clocksPerSample = Some(8), cordicUnits = Some(1), storage = Some(Storage.Memory)),
        routed = true,
        composeParallelAxes = true
      )
      runRobot("planar3", 49L, ScheduleRequest(clocksPerSample = Some(6), storage = Some(Storage.Memory)))
    }

  it should "fit the UR5 with block-RAM banks at 64 and 88 clocks per sample and a 1e-3 N·m " +
    "target, bit-exact under back-pressure" in {
      runRobot(
        "ur5",
        52L,
        ScheduleRequest(clocksPerSample = Some(64), storage = Some(Storage.Memory)),
        targetError = Seq(1e-3)
      )
      runRobot(
        "ur5",
        56L,
        ScheduleRequest(clocksPerSample = Some(88), storage = Some(Storage.Memory)),
        targetError = Seq(1e-3)
      )
    }

  it should "meet a 1e-3 N·m target on the UR5 with registered routes at 17 clocks per sample, the sweep's " +
    "routed point, in 66 blocks, on the solver's shortest schedule, products sharing registers, those of " +
    "slack 0 forwarded, bit-exact " +
    "under back-pressure" in {
      runRobot(
        "ur5",
        48L,
        ScheduleRequest(
          clocksPerSample = Some(17),
          maxMultipliers = Some(66),
          listOrder = Some(ListOrder.ByHeight),
          refinement = reducerload.app.ArmSweep.fastRefinement,
          scheduler = Scheduler.CpSat,
          shareRegisters = true,
          forwardSlack = Some(0)
        ),
        targetError = Seq(1e-3),
        reassociate = Reassociation.Sums,
        routed = true,
        memoryDelayMinCycles = Some(0)
      )
    }

  it should "cross the UR5's parallel axes in issue 33's latency recipe (18 clocks per sample, 66 blocks, " +
    "registered routes, CP-SAT, reassociated, accumulators, product and sin/cos memories, " +
    "shared registers, 1e-3 N·m), bit-exact under back-pressure" in {
      runRobot(
        "ur5",
        69L,
        ScheduleRequest(
          clocksPerSample = Some(18),
          maxMultipliers = Some(66),
          listOrder = Some(ListOrder.ByHeight),
          refinement = reducerload.app.ArmSweep.fastRefinement,
          scheduler = Scheduler.CpSat,
          accumulateSlack = Some(9),
          productMemories = true,
          shareRegisters = true,
          sinCosMemories = true
        ),
        targetError = Seq(1e-3),
        reassociate = Reassociation.SumsAndProducts,
        routed = true,
        memoryDelayMinCycles = Some(34),
        composeParallelAxes = true
      )
    }

  it should "fit the UR5 with reassociated sums, placed by height, refined as the sweep's fast point, in the " +
    "66 multiplier blocks of an EP4CE30 with a 1e-3 N·m target, bit-exact under back-pressure" in {
      runRobot(
        "ur5",
        58L,
        ScheduleRequest(
          clocksPerSample = None,
          maxMultipliers = Some(66),
          listOrder = Some(ListOrder.ByHeight),
          refinement = reducerload.app.ArmSweep.fastRefinement
        ),
        targetError = Seq(1e-3),
        reassociate = Reassociation.Sums
      )
    }
}
