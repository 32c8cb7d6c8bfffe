package reducerload.arm

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.compiler.Compiler
import reducerload.config.{LoadParams, PayloadSettings, Settings}
import reducerload.dynamics.{RandomChains, Rnea}
import reducerload.graph.{GraphReference, InertialParameter, Signal}
import reducerload.robot.{Mat3, RigidBody, Vec3}
import reducerload.sim.model.FastArmModel
import reducerload.testutil.{ArmGolden, Seeds}
import reducerload.util.InputError

import scala.util.Random

/**
 * The run-time payload (issue 31): its ten inertial parameters are graph inputs with declared ranges. Checked
 * with no Python: the graph's double reference equals RNEA on the chain whose last body is merged with the
 * payload (an independent path: RigidBody.transformed and merge); the bit-accurate model is within the
 * derived bound of it over random payloads in the declared set; payloads beyond it are clamped and flagged.
 */
class PayloadSpecSpec extends AnyFlatSpec {
  behavior of "a run-time payload"

  /** The robot of the golden traces, with a payload of at most `maxMass` kg. */
  private def params(robot: String, maxMass: Double, frame: String = ""): ArmParams =
    Compiler.arm(
      ArmGolden
        .of(robot)
        .head
        .config
        .copy(payload = PayloadSettings(enabled = true, maxMass = maxMass, frame = frame))
    )

  /**
   * A payload in the declared set: mass up to the maximum, centre of mass in the ball of com-radius, inertia
   * about it a random rotation of principal moments of at most m r^2 that meet the triangle inequality.
   */
  private def randomPayload(rng: Random, spec: PayloadSpec, scale: Double = 1.0): RigidBody = {
    val m = rng.nextDouble() * spec.maxMass * scale
    def unit() = {
      val v = Vec3(rng.nextGaussian(), rng.nextGaussian(), rng.nextGaussian()); v * (1 / v.norm)
    }
    val c = unit() * (spec.comRadius * scale * math.cbrt(rng.nextDouble()))
    val top = m * spec.maxGyrationRadius * spec.maxGyrationRadius * scale
    val a = rng.nextDouble() * top / 2
    val b = rng.nextDouble() * top / 2
    val moments = Vec3(a + b, a + rng.nextDouble() * b, b + rng.nextDouble() * a) // triangle inequality
    val axis = unit()
    val rotation = Mat3.axisAngle(axis, rng.nextDouble() * 2 * math.Pi)
    RigidBody(m, c, rotation * Mat3.diagonal(moments) * rotation.transpose)
  }

  private def sample(rng: Random, p: ArmParams): ArmSample = {
    val (q, qd, qdd) = RandomChains.sample(rng, p.maxVelocity, p.maxAcceleration)
    ArmSample(q, qd, qdd)
  }

  private def check(robot: String, maxMass: Double, seed: Long): Unit = {
    val p = params(robot, maxMass)
    val spec = p.payload.get
    val model = new ArmModel(p)
    val fast = new FastArmModel(p)
    val rng = new Random(Seeds(s"payload-$robot", seed))
    val worstRef = Array.fill(p.chain.size)(0.0)
    val worstHw = Array.fill(p.chain.size)(0.0)
    (0 until 300).foreach { k =>
      val body = if (k == 0) RigidBody.massless else randomPayload(rng, spec)
      val s = sample(rng, p)
      spec.ranges(p.chain).foreach { case (sig, range) =>
        val v = spec.values(p.chain, body)(sig)
        assert(v >= range.lo && v <= range.hi, s"$robot: test payload $sig = $v outside $range")
      }
      val merged = Rnea.reference(spec.merged(p.chain, body), s.q, s.qd, s.qdd)
      val graph = GraphReference.outputs(p.graph, s.q, s.qd, s.qdd, spec.values(p.chain, body))
      merged.indices.foreach(j => worstRef(j) = math.max(worstRef(j), math.abs(graph(j) - merged(j))))
      val codes = model.encode(s, body)
      val out = model.evaluate(codes)
      assert(out == fast.evaluate(codes), s"$robot sample $k: the long model differs from the model")
      assert(!out.outOfRange.exists(identity), s"$robot sample $k: an in-range payload was flagged")
      model.torques(out).zip(merged).zipWithIndex.foreach { case ((h, r), j) =>
        worstHw(j) = math.max(worstHw(j), math.abs(h - r))
      }
    }
    p.chain.joints.indices.foreach { j =>
      println(
        f"[payload] $robot ${p.jointNames(j)}%-22s |graph reference - merged RNEA| ${worstRef(j)}%.2e, " +
          f"|model - merged RNEA| ${worstHw(j)}%.3e N·m (bound ${p.errorBounds(j)}%.3e)"
      )
      assert(worstRef(j) <= 1e-9, s"$robot ${p.jointNames(j)}: graph reference off by ${worstRef(j)}")
      assert(worstHw(j) <= p.errorBounds(j), s"$robot ${p.jointNames(j)}: ${worstHw(j)} above the bound")
      assert(worstHw(j) <= 1e-3, s"$robot ${p.jointNames(j)}: ${worstHw(j)} above 1e-3 N·m")
    }
    println(
      s"[payload] $robot: ${p.graph.counts}, bound ${p.errorBound} N·m, payload formats " +
        p.numerics.parameters.map(s => s"$s ${p.numerics.parameterFormats(s)}").mkString(", ")
    )
  }

  it should "give the UR5 the torques of RNEA with the payload merged into its last body, within the " +
    "derived bound and 1e-3 N·m" in {
      check("ur5", 5.0, 3101L)
    }

  it should "give the Panda the torques of RNEA with the payload merged into its last body, within the " +
    "derived bound and 1e-3 N·m" in {
      check("panda", 3.0, 3102L)
    }

  it should "clamp and flag a payload beyond the declared set, never wrap it" in {
    val p = params("ur5", 5.0)
    val spec = p.payload.get
    val model = new ArmModel(p)
    val fast = new FastArmModel(p)
    val rng = new Random(Seeds("payload-clamp", 3103L))
    (0 until 100).foreach { k =>
      val s = sample(rng, p)
      val body = randomPayload(rng, spec, scale = 3.0)
      val values = spec.values(p.chain, body)
      val outside = spec.ranges(p.chain).exists { case (sig, r) => values(sig) < r.lo || values(sig) > r.hi }
      // The same payload with every parameter clamped to its interval, in range.
      val clamped = spec.ranges(p.chain).collect { case (sig: Signal.Inertial, r) =>
        sig.parameter -> math.max(r.lo, math.min(r.hi, values(sig)))
      }
      def at(i: InertialParameter) = clamped(i)
      val inRange = RigidBody(
        at(InertialParameter.Mass),
        Vec3((0 until 3).map(a => at(InertialParameter.Com(a)))),
        Mat3.tabulate((r, c) => at(InertialParameter.Inertia(math.min(r, c), math.max(r, c))))
      )
      val out = model.evaluate(model.encode(s, body))
      assert(out == fast.evaluate(model.encode(s, body)), s"sample $k: the long model differs from the model")
      val expected = model.evaluate(model.encode(s, inRange))
      assert(out.tau == expected.tau, s"sample $k: an out-of-range payload is not computed clamped")
      assert(out.outOfRange.forall(_ == outside), s"sample $k: flags ${out.outOfRange}, outside = $outside")
    }
    // A mass far beyond the port format saturates there, then clamps: never wraps.
    val s = sample(rng, p)
    val heavy = RigidBody(1e6, Vec3.zero, Mat3.zero)
    val out = model.evaluate(model.encode(s, heavy))
    assert(out.outOfRange.forall(identity))
    assert(out.tau == model.evaluate(model.encode(s, RigidBody(5.0, Vec3.zero, Mat3.zero))).tau)
    val light = model.evaluate(model.encode(s, RigidBody(-1.0, Vec3.zero, Mat3.zero)))
    assert(light.outOfRange.forall(identity))
    assert(light.tau == model.evaluate(model.encode(s, RigidBody.massless)).tau)
  }

  /** The body of ten parameter values by signal (the inertia symmetric). */
  private def bodyOf(values: Map[Signal.Parameter, Double]): RigidBody = {
    val v = values.collect { case (s: Signal.Inertial, x) => s.parameter -> x }
    RigidBody(
      v(InertialParameter.Mass),
      Vec3((0 until 3).map(a => v(InertialParameter.Com(a)))),
      Mat3.tabulate((r, c) => v(InertialParameter.Inertia(math.min(r, c), math.max(r, c))))
    )
  }

  for ((robot, maxMass, seed) <- Seq(("ur5", 5.0, 3108L), ("panda", 3.0, 3109L)))
    it should s"clamp and flag each parameter alone beyond its interval on the $robot (mass above the maximum or " +
      "negative, centre of mass beyond the radius, inertia beyond the bound or negative), never wrap it" in {
        val p = params(robot, maxMass)
        val spec = p.payload.get
        val model = new ArmModel(p)
        val fast = new FastArmModel(p)
        val rng = new Random(Seeds(s"payload-clamp-each-$robot", seed))
        val ranges = spec.ranges(p.chain)
        var cases = 0
        Signal.inertial(spec.joint(p.chain)).foreach { sig =>
          val r = ranges(sig)
          val width = r.hi - r.lo
          // Just beyond either end, and far beyond the port format (saturates there first, then clamps).
          val beyond = Seq(r.hi + width * (0.01 + rng.nextDouble()), r.lo - width * (0.01 + rng.nextDouble()))
          (beyond ++ Seq(1e9, -1e9)).foreach { x =>
            val s = sample(rng, p)
            val values = spec.values(p.chain, randomPayload(rng, spec)).updated(sig, x)
            val clamped = values.updated(sig, math.max(r.lo, math.min(r.hi, x)))
            val codes = model.encode(s, bodyOf(values))
            val out = model.evaluate(codes)
            val expected = model.evaluate(model.encode(s, bodyOf(clamped)))
            assert(out == fast.evaluate(codes), s"$robot $sig = $x: the long model differs from the model")
            assert(!expected.outOfRange.exists(identity), s"$robot $sig clamped to ${clamped(sig)}: flagged")
            assert(out.outOfRange.forall(identity), s"$robot $sig = $x: flags ${out.outOfRange}")
            assert(out.tau == expected.tau, s"$robot $sig = $x: not computed with the clamped value")
            cases += 1
          }
        }
        println(s"[payload] $robot: $cases single parameters beyond their intervals clamped and flagged")
      }

  it should "state the payload in any link fixed to the last moving joint, and refuse others in one line" in {
    val flange = params("panda", 3.0, frame = "panda_link8")
    val hand = params("panda", 3.0)
    assert(flange.payload.get.pose != hand.payload.get.pose, "panda_link8 and panda_hand are apart")
    assert(hand.payload.get.frame == "panda_hand")
    val rng = new Random(Seeds("payload-frame", 3104L))
    val s = sample(rng, hand)
    // The same body stated in the hand and in the flange: the same torques.
    val inHand = randomPayload(rng, hand.payload.get)
    val toFlange = flange.payload.get.pose
    val flangeFromHand = reducerload.robot.Transform(
      toFlange.rotation.transpose * hand.payload.get.pose.rotation,
      toFlange.rotation.transpose * (hand.payload.get.pose.translation - toFlange.translation)
    )
    val a = GraphReference.outputs(hand.graph, s.q, s.qd, s.qdd, hand.payload.get.values(hand.chain, inHand))
    val b = GraphReference.outputs(
      flange.graph,
      s.q,
      s.qd,
      s.qdd,
      flange.payload.get.values(flange.chain, inHand.transformed(flangeFromHand))
    )
    a.zip(b).foreach { case (x, y) => assert(math.abs(x - y) <= 1e-9) }
    def refusal(frame: String) =
      intercept[InputError](
        Compiler.compile(
          ArmGolden
            .of("panda")
            .head
            .config
            .copy(payload = PayloadSettings(enabled = true, maxMass = 3.0, frame = frame)),
          "test"
        )
      ).getMessage
    val moving = refusal("panda_link3")
    assert(moving.contains("payload.frame") && moving.contains("not fixed to the last moving joint"), moving)
    assert(!moving.contains("\n"))
    val unknown = refusal("no_such_link")
    assert(
      unknown.contains("payload.frame") && unknown.contains("'no_such_link' is not fixed") &&
        unknown.contains("links it carries: panda_hand"),
      unknown
    )
  }

  it should "need a declared max-mass, and change nothing while disabled" in {
    val undeclared = intercept[InputError](
      Settings.withOverrides(
        LoadParams.arm,
        Seq(reducerload.config.Assignment(Settings.payloadEnabled, true)),
        "flags"
      )
    ).getMessage
    assert(undeclared.contains("payload.max-mass"), undeclared)
    val plain = Compiler.arm(ArmGolden.of("ur5").head.config)
    assert(plain.payload.isEmpty && plain.numerics.parameters.isEmpty)
    assert(!plain.graph.signals.exists(_.isInstanceOf[Signal.Inertial]))
    val withPayload = params("ur5", 5.0)
    assert(withPayload.graph.signals.count(_.isInstanceOf[Signal.Inertial]) == 10)
    assert(withPayload.moduleName != plain.moduleName)
  }

  it should "take a run-time gravity with and without the payload: within the bound of RNEA under that gravity, clamped and flagged beyond it" in {
    val config =
      ArmGolden.of("ur5").head.config.copy(gravity = reducerload.config.GravitySettings(runtime = true))
    for (withPayload <- Seq(false, true)) {
      val p = Compiler.arm(
        if (withPayload) config.copy(payload = PayloadSettings(enabled = true, maxMass = 5.0)) else config
      )
      val bound = p.gravity.get.maxMagnitude
      val model = new ArmModel(p)
      val fast = new FastArmModel(p)
      val rng = new Random(Seeds(s"gravity-runtime-$withPayload", 3106L))
      var worst = 0.0
      (0 until 200).foreach { k =>
        val s = sample(rng, p)
        val body = p.payload.fold(RigidBody.massless)(randomPayload(rng, _))
        val scale = if (k % 2 == 0) 1.0 else 1.8 // every other one may lie beyond the box
        val g = Vec3(rng.nextGaussian(), rng.nextGaussian(), rng.nextGaussian()) * (bound / 2 * scale)
        val clamped = Vec3(g.toSeq.map(x => math.max(-bound, math.min(bound, x))))
        val outside = clamped != g
        val out = model.evaluate(model.encode(s, body, g))
        assert(out == fast.evaluate(model.encode(s, body, g)), s"sample $k: the long model differs")
        assert(out.outOfRange.forall(_ == outside), s"sample $k: flags ${out.outOfRange}, outside = $outside")
        if (outside)
          assert(out.tau == model.evaluate(model.encode(s, body, clamped)).tau, s"sample $k: not clamped")
        else {
          val chain = p.payload.fold(p.chain)(_.merged(p.chain, body)).copy(gravity = g)
          val ref = Rnea.reference(chain, s.q, s.qd, s.qdd)
          val graph = GraphReference.outputs(
            p.graph,
            s.q,
            s.qd,
            s.qdd,
            p.gravity.get.values(g) ++ p.payload.fold(Map.empty[Signal.Parameter, Double])(
              _.values(p.chain, body)
            )
          )
          graph.zip(ref).foreach { case (a, b) =>
            assert(math.abs(a - b) < 1e-9, s"sample $k: graph reference")
          }
          model.evaluate(model.encode(s, body, g)).tau.indices.foreach { j =>
            val e = math.abs(model.torques(out)(j) - ref(j))
            assert(e <= p.errorBounds(j), s"sample $k joint ${j + 1}: $e above ${p.errorBounds(j)}")
            worst = math.max(worst, e)
          }
        }
      }
      println(
        f"[gravity] ur5 gravity.runtime, payload $withPayload: worst |model - RNEA| $worst%.3e N·m, bound " +
          f"${p.errorBound}%.3e, ${p.graph.counts}"
      )
    }
  }
}
