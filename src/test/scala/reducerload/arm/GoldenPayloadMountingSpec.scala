package reducerload.arm

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.compiler.Compiler
import reducerload.dynamics.Rnea
import reducerload.robot.{Mounting, RigidBody, Vec3}
import reducerload.testutil.ArmGolden

/**
 * The Pinocchio traces of golden/arms/mounting and golden/arms/payload (make_golden_payload.py) against the
 * double reference: the mounted UR5 built with the trace's `robot.base-rpy` (and its bit-accurate model
 * within the derived bound and 1e-3 N·m), and the UR5 and the Panda with the payload merged into the last
 * body at its frame's placement, and their bit-accurate models with `payload.enabled` fed each row's payload
 * within each joint's derived bound and 1e-3 N·m (the payload hardware is PayloadedArmSpec's).
 */
class GoldenPayloadMountingSpec extends AnyFlatSpec {
  behavior of "The payload and mounting golden traces"

  /**
   * N·m. Pinocchio and the traces' own checks agree to 1e-13; the UR5's URDF writes pi/2 as 1.57079632679
   * (5e-12 rad short), which Mat3.rpy snaps to exact zeros and ones: that alone moves its torques by up to
   * 8e-10 N·m (the Panda's full-precision angles agree to 1e-13).
   */
  private val tolerance = 1e-9

  private def worst(a: Seq[IndexedSeq[Double]], b: Seq[IndexedSeq[Double]]): Double =
    a.zip(b).map { case (x, y) => x.zip(y).map { case (u, v) => math.abs(u - v) }.max }.max

  /**
   * Per joint: the model's torques `hw` within the derived bound of the double reference `ref`, and within
   * the bound (plus doubles' rounding) and the 1e-3 N·m target of Pinocchio's `pin`.
   */
  private def withinBounds(
      label: String,
      p: ArmParams,
      hw: Seq[IndexedSeq[Double]],
      ref: Seq[IndexedSeq[Double]],
      pin: Seq[IndexedSeq[Double]]
  ): Unit =
    p.graph.outputs.indices.foreach { j =>
      def off(against: Seq[IndexedSeq[Double]]) =
        hw.zip(against).map { case (h, r) => math.abs(h(j) - r(j)) }.max
      val (vsRef, vsPin) = (off(ref), off(pin))
      println(
        f"[golden] $label ${p.graph.outputs(j).name}%-20s max |model - pinocchio| $vsPin%.3e N·m " +
          f"(bound ${p.errorBounds(j)}%.3e)"
      )
      assert(vsRef <= p.errorBounds(j), s"$label joint ${j + 1}: $vsRef above the bound ${p.errorBounds(j)}")
      assert(vsPin <= p.errorBounds(j) + 1e-9 && vsPin <= ArmChecks.target, s"$label joint ${j + 1}: $vsPin")
    }

  it should "read the mounting as the trace's base-rpy and rotate the UR5's gravity by it" in {
    val traces = ArmGolden.mounted("ur5")
    assert(traces.map(_.mounting.name.getOrElse("tilt")).toSet == Set("ceiling", "tilt"))
    traces.foreach { t =>
      assert(t.payloads.forall(_.isEmpty) && t.payloadRanges.isEmpty)
      val expected =
        if (t.mounting == Mounting.ceiling) Vec3(0, 0, 9.81)
        else {
          val (c, s) = (math.cos(math.Pi / 6), math.sin(math.Pi / 6))
          assert(t.mounting == Mounting(0, math.Pi / 6, 0))
          Vec3(9.81 * s, 0, -9.81 * c)
        }
      assert((t.chain.gravity - expected).norm < 1e-12, s"${t.name}: gravity ${t.chain.gravity}")
    }
  }

  it should "match Pinocchio on the ceiling-mounted and the tilted UR5 (the double reference within 1e-9 N·m)" in {
    ArmGolden.mounted("ur5").foreach { t =>
      val ref = t.samples.map(s => Rnea.reference(t.chain, s.q, s.qd, s.qdd))
      val err = worst(ref, t.torques)
      println(
        f"[golden] ${t.name} (${t.mounting}): max |rnea - pinocchio| $err%.2e N·m over ${t.samples.size} rows"
      )
      assert(err < tolerance, s"${t.name}: $err N·m")
      // The same samples on the floor-mounted chain are far off: the check sees the mounting.
      val floor = t.config.robot.copy(mounting = Mounting.floor).chain
      val unmounted = worst(t.samples.map(s => Rnea.reference(floor, s.q, s.qd, s.qdd)), t.torques)
      assert(unmounted > 1.0, s"${t.name}: the floor-mounted chain is only $unmounted N·m off")
    }
  }

  it should "compute the mounted UR5 bit-accurately (ArmModel, FastArmModel) within each joint's derived bound and 1e-3 N·m of Pinocchio" in {
    ArmGolden.mounted("ur5").groupBy(_.mounting).toSeq.sortBy(_._1.toString).foreach {
      case (mounting, traces) =>
        val p = Compiler.arm(traces.head.config)
        assert(p.chain.gravity == traces.head.chain.gravity)
        println(s"[golden] ur5 $mounting: gravity ${p.chain.gravity}, ${p.graph.counts}")
        // The report (and the emitted Verilog's header) states the folded gravity vector.
        val gravity = s"gravity ${p.chain.gravity.toSeq.mkString("(", ", ", ")")} m/s^2"
        assert(reducerload.app.ArmReport(p, "ur5", "test").summaryLines.exists(_.contains(gravity)), gravity)
        assert(p.errorBound <= ArmChecks.target, s"$mounting: derived bound ${p.errorBound}")
        val model = new ArmModel(p)
        val samples = traces.flatMap(_.samples)
        val codes = samples.map(model.encode)
        val out = codes.map(model.evaluate)
        // The replay's long-integer model, bit for bit the same.
        val fast = new reducerload.sim.model.FastArmModel(p)
        assert(reducerload.sim.model.FastArmModel.supports(p))
        assert(
          codes.zip(out).forall { case (c, o) => fast.evaluate(c) == o },
          s"$mounting: FastArmModel differs"
        )
        val hw = out.map(model.torques)
        val pin = traces.flatMap(_.torques)
        val dbl = samples.map(s => Rnea.reference(p.chain, s.q, s.qd, s.qdd))
        withinBounds(s"ur5 $mounting", p, hw, dbl, pin)
    }
  }

  it should "compute the ceiling and tilted UR5 on the floor-mounted design with gravity.runtime, fed their gravity vectors (the model within its bound and 1e-3 N·m of Pinocchio, the graph reference within 1e-9)" in {
    val traces = ArmGolden.mounted("ur5")
    val floor = traces.head.config.copy(
      robot = traces.head.config.robot.copy(mounting = Mounting.floor),
      gravity = reducerload.config.GravitySettings(runtime = true)
    )
    val p = Compiler.arm(floor)
    assert(p.chain.gravity == Vec3(0, 0, -9.81), s"the design's reset gravity ${p.chain.gravity}")
    assert(p.numerics.parameters == reducerload.graph.Signal.gravity)
    println(s"[golden] ur5 gravity.runtime: ${p.graph.counts}, derived bound ${p.errorBound}")
    assert(p.errorBound <= ArmChecks.target, s"derived bound ${p.errorBound}")
    val model = new ArmModel(p)
    val fast = new reducerload.sim.model.FastArmModel(p)
    traces.foreach { t =>
      val g = t.chain.gravity
      val codes = t.samples.map(s => model.encode(s, RigidBody.massless, g))
      val out = codes.map(model.evaluate)
      assert(
        codes.zip(out).forall { case (c, o) => fast.evaluate(c) == o },
        s"${t.name}: FastArmModel differs"
      )
      assert(out.forall(!_.outOfRange.exists(identity)), s"${t.name}: a sample flagged")
      val hw = out.map(model.torques)
      val graphRef = t.samples.map(s =>
        reducerload.graph.GraphReference.outputs(p.graph, s.q, s.qd, s.qdd, p.gravity.get.values(g))
      )
      val dbl = worst(graphRef, t.torques)
      assert(dbl < tolerance, s"${t.name}: the graph reference is $dbl N·m from Pinocchio")
      withinBounds(
        f"${t.name} on gravity.runtime (graph reference $dbl%.1e from Pinocchio)",
        p,
        hw,
        graphRef,
        t.torques
      )
      // The reset (floor) gravity is far off: the check sees the fed gravity.
      val asFloor = t.samples.map(s => model.torques(model.evaluate(model.encode(s))))
      assert(worst(asFloor, t.torques) > 1.0, s"${t.name}: the floor gravity is as good")
    }
  }

  it should "leave the graph unchanged with gravity.runtime off, and take three gravity inputs with it" in {
    val config = ArmGolden.of("ur5").head.config
    val plain = Compiler.arm(config)
    val off = Compiler.arm(config.copy(gravity = reducerload.config.GravitySettings(maxMagnitude = 20.0)))
    assert(plain.graph == off.graph && plain.numerics == off.numerics && plain.moduleName == off.moduleName)
    val on = Compiler.arm(config.copy(gravity = reducerload.config.GravitySettings(runtime = true)))
    assert(on.graph.signals.collect { case g: reducerload.graph.Signal.Gravity => g }.size == 3)
    assert(
      on.numerics.parameterRanges.values.forall(_ == reducerload.graph.Interval.symmetric(1.5 * 9.80665))
    )
    val low = intercept[reducerload.util.InputError](
      Compiler.arm(
        config.copy(gravity = reducerload.config.GravitySettings(runtime = true, maxMagnitude = 5.0))
      )
    )
    assert(low.getMessage.contains("gravity.max-magnitude"), low.getMessage)
  }

  for (robot <- Seq("ur5", "panda"))
    it should s"match Pinocchio on the $robot carrying payloads (the last body merged with the payload, within 1e-9 N·m)" in {
      val traces = ArmGolden.withPayload(robot)
      assert(traces.map(_.name).toSet == Set(s"payload/${robot}_random", s"payload/${robot}_pick_and_place"))
      traces.foreach { t =>
        val ranges = t.payloadRanges.getOrElse(fail(s"${t.name}: no declared payload ranges"))
        assert(ranges.maxMass == (if (robot == "ur5") 5.0 else 3.0) && ranges.comRadius == 0.1)
        assert(ranges.frame == t.config.robot.tip)
        val payloads = t.payloads.map(_.getOrElse(fail(s"${t.name}: a row without payload")))
        payloads.foreach { b =>
          assert(b.mass >= 0 && b.mass <= ranges.maxMass)
          assert(b.com.norm <= ranges.comRadius + 1e-12)
          assert(b.inertia.rows.flatten.forall(x => math.abs(x) <= ranges.maxInertia))
          assert(b.inertia == b.inertia.transpose)
        }
        assert(payloads.exists(_.mass == 0) && payloads.exists(_.mass == ranges.maxMass))
        assert(payloads.exists(b => math.abs(b.com.norm - ranges.comRadius) < 1e-12))
        val changes = payloads.zip(payloads.drop(1)).count { case (a, b) => a != b }
        if (t.name.endsWith("pick_and_place")) assert(changes >= 3, s"${t.name}: $changes payload changes")
        val ref = t.samples.indices.map { i =>
          val s = t.samples(i)
          Rnea.reference(t.chain.carrying(ranges.frame, payloads(i)), s.q, s.qd, s.qdd)
        }
        val err = worst(ref, t.torques)
        val bare = worst(t.samples.map(s => Rnea.reference(t.chain, s.q, s.qd, s.qdd)), t.torques)
        println(
          f"[golden] ${t.name}: max |rnea with payload - pinocchio| $err%.2e N·m over ${t.samples.size} rows " +
            f"($changes payload changes; without the payload $bare%.1f N·m off)"
        )
        assert(err < tolerance, s"${t.name}: $err N·m")
        assert(bare > 1.0, s"${t.name}: the payload moves the torques by only $bare N·m")
      }
    }

  for ((robot, maxMass) <- Seq("ur5" -> 5.0, "panda" -> 3.0))
    it should s"compute the $robot with payload.enabled on every golden payload row bit-accurately (ArmModel, FastArmModel) within each joint's derived bound and 1e-3 N·m of Pinocchio" in {
      val traces = ArmGolden.withPayload(robot)
      val p = Compiler.arm(
        traces.head.config
          .copy(payload = reducerload.config.PayloadSettings(enabled = true, maxMass = maxMass))
      )
      val spec = p.payload.get
      assert(traces.forall(_.payloadRanges.exists(r => r.frame == spec.frame && r.maxMass == spec.maxMass)))
      val model = new ArmModel(p)
      val fast = new reducerload.sim.model.FastArmModel(p)
      val rows = traces.flatMap(t => t.samples.zip(t.payloads.map(_.get)))
      val codes = rows.map { case (s, b) => model.encode(s, b) }
      val out = codes.map(model.evaluate)
      assert(codes.zip(out).forall { case (c, o) => fast.evaluate(c) == o }, s"$robot: FastArmModel differs")
      assert(out.forall(!_.outOfRange.exists(identity)), s"$robot: a golden payload row flagged")
      val merged = rows.map { case (s, b) => Rnea.reference(spec.merged(p.chain, b), s.q, s.qd, s.qdd) }
      println(
        s"[golden] $robot payload (max ${spec.maxMass} kg in ${spec.frame}; the model is that of every " +
          s"schedule): ${rows.size} rows of ${traces.map(_.name).mkString(", ")}"
      )
      withinBounds(s"$robot payload", p, out.map(model.torques), merged, traces.flatMap(_.torques))
      // Without the payload the same rows are far off: the check sees the payload.
      val bare = rows.map { case (s, _) => model.torques(model.evaluate(model.encode(s))) }
      assert(worst(bare, traces.flatMap(_.torques)) > 1.0, s"$robot: the payload changes nothing")
    }

  it should "offer the payload frames the last joint carries, at their URDF placement" in {
    val ur5 = ArmGolden.of("ur5").head.chain
    assert(Set("wrist_3_link", "tool0").subsetOf(ur5.tipFrames.keySet))
    assert(ur5.tipFrames("wrist_3_link") == reducerload.robot.Transform.identity)
    val panda = ArmGolden.of("panda").head.chain
    assert(Set("panda_link7", "panda_link8", "panda_hand").subsetOf(panda.tipFrames.keySet))
    assert(!panda.tipFrames.contains("panda_link6"))
    assert(math.abs(panda.tipFrames("panda_hand").translation.z - 0.107) < 1e-15)
    assert(panda.tipFrames("panda_hand").rotation.isFinite)
    assert(
      intercept[IllegalArgumentException](panda.carrying("panda_link6", RigidBody.massless)).getMessage
        .contains("panda_link6")
    )
    // planar3: a payload at the tip adds to m3's point mass.
    val planar = reducerload.robot.Planar3.chain()
    val link3 = planar.carrying("tip", RigidBody.pointMass(2.0, Vec3.zero)).joints(2).body
    assert(link3.mass == 12.0 && (link3.com - Vec3(0.3, 0, 0)).norm < 1e-15)
    assert(link3.inertia.rows.flatten.forall(x => math.abs(x) < 1e-15))
  }
}
