package reducerload.arm

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.compiler.Compiler
import reducerload.config.{GravitySettings, PayloadSettings}
import reducerload.dynamics.{RandomChains, Rnea}
import reducerload.fixedpoint.Rounding
import reducerload.graph.{InertialParameter, SampleCodes, ScheduleRequest, Signal, Storage}
import reducerload.robot.{Mat3, RigidBody, Vec3}
import reducerload.testutil.{ArmGolden, Seeds, SimBackend}

import scala.collection.mutable.ArrayBuffer
import scala.util.Random
import reducerload.testutil.SimBackend.multiplierImpl // the JVM simulator builds the multipliers' Chisel twin

/**
 * The UR5 with a run-time payload and run-time gravity at a shared block-RAM schedule, through its parameter
 * registers: the host writes payloads and gravity vectors (some beyond the declared sets) and commits them at
 * random times while samples stream with bubbles, back-pressure and resets. Checked cycle by cycle: every
 * sample's torques and flags bit-exact with the model for the payload and gravity committed when it was
 * taken, at exactly the latency, with their sequence number; in-range torques within the derived bound of
 * RNEA with the payload merged into the last body and the committed gravity. One Verilator design for both.
 */
class PayloadedArmSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "PayloadedArm"

  it should "compute every UR5 sample with the payload and gravity committed when it was taken, bit-exact " +
    "with the model, and say which" in {
      val p = Compiler.arm(
        ArmGolden
          .of("ur5")
          .head
          .config
          .copy(
            payload = PayloadSettings(enabled = true, maxMass = 5.0),
            gravity = GravitySettings(runtime = true),
            schedule = ScheduleRequest(clocksPerSample = Some(88), storage = Some(Storage.Memory))
          )
      )
      val spec = p.payload.get
      val gravitySpec = p.gravity.get
      val model = new ArmModel(p)
      val params = p.numerics.parameters
      val port = p.numerics.parameterPortFormat
      val rng = new Random(Seeds("payloaded-arm-ur5", 3105L))
      def payload(): RigidBody = {
        val scale = if (rng.nextDouble() < 0.2) 2.5 else 1.0 // some beyond the declared set
        val m = rng.nextDouble() * spec.maxMass * scale
        def coord() = (rng.nextDouble() * 2 - 1) * spec.comRadius * scale / math.sqrt(3)
        val top = m * spec.maxGyrationRadius * spec.maxGyrationRadius * scale
        val d = Vec3(rng.nextDouble() * top, rng.nextDouble() * top, rng.nextDouble() * top) * 0.5
        RigidBody(m, Vec3(coord(), coord(), coord()), Mat3.diagonal(d))
      }
      // A gravity of random direction, mostly within the declared magnitude, some components beyond it.
      def gravity(): Vec3 = {
        val scale = if (rng.nextDouble() < 0.2) 1.6 else 1.0
        val d = Vec3(rng.nextGaussian(), rng.nextGaussian(), rng.nextGaussian())
        d * (rng.nextDouble() * gravitySpec.maxMagnitude * scale / d.norm)
      }
      def code(x: Double) = port.fromDouble(x, Rounding.HalfUp)._1
      // The writes of a payload or of a gravity vector, (register index, code) each.
      def writesOf(values: Map[Signal.Parameter, Double]): List[(Int, BigInt)] =
        params.zipWithIndex.collect { case (s, k) if values.contains(s) => (k, code(values(s))) }.toList
      val inertial = params.collect { case s: Signal.Inertial => s }
      def bodyOf(codes: IndexedSeq[BigInt]): RigidBody = {
        val v = inertial.map(_.parameter).zip(codes.map(port.toDouble)).toMap
        RigidBody(
          v(InertialParameter.Mass),
          Vec3((0 until 3).map(a => v(InertialParameter.Com(a)))),
          Mat3.tabulate((r, c) => v(InertialParameter.Inertia(math.min(r, c), math.max(r, c))))
        )
      }
      val cycles = SimBackend.scale(120) * p.schedule.clocksPerSample
      val resetAt = Set(cycles / 3, 2 * cycles / 3)
      val seqMod = 1 << PayloadedArm.sequenceBits

      test(new PayloadedArm(p)).withAnnotations(SimBackend.annotations) { dut =>
        // The registers' model: staged, active, sequence.
        var staged = PayloadedArm.resetCodes(p)
        var active = staged
        var sequence = 0
        var writes = List.empty[(Int, BigInt)] // a payload being written, one parameter per cycle
        var sample = Option.empty[ArmSample]
        val taken = ArrayBuffer.empty[(Int, SampleCodes, Int)] // cycle, codes, sequence
        val outputs = ArrayBuffer.empty[(Int, ArmOutputCodes, Int)]
        var lastReset = -1
        (0 until cycles + p.latency + 2).foreach { t =>
          val doReset = resetAt(t)
          dut.reset.poke(doReset.B)
          if (doReset) {
            staged = PayloadedArm.resetCodes(p); active = staged; sequence = 0; writes = Nil
            lastReset = t
          }
          // Host: write a fresh payload or gravity parameter by parameter, commit at random times.
          if (!doReset && writes.isEmpty && rng.nextDouble() < 0.03)
            writes =
              if (rng.nextBoolean()) writesOf(spec.values(p.chain, payload()))
              else writesOf(gravitySpec.values(gravity()))
          val write = if (doReset) None else writes.headOption
          writes = if (doReset) Nil else writes.drop(1)
          val commit = !doReset && rng.nextDouble() < 0.03
          dut.io.host.write.valid.poke(write.isDefined.B)
          write.foreach { case (k, c) =>
            dut.io.host.write.bits.index.poke(k.U)
            dut.io.host.write.bits.value.poke(c.S)
          }
          dut.io.host.commit.poke(commit.B)
          // Samples: offered with bubbles, held until taken.
          if (sample.isEmpty && t < cycles && rng.nextDouble() < 0.5) {
            val (q, qd, qdd) =
              RandomChains.sample(rng, p.maxVelocity.map(_ * 1.05), p.maxAcceleration.map(_ * 1.05))
            sample = Some(ArmSample(q, qd, qdd))
          }
          dut.io.in.valid.poke((sample.isDefined && !doReset).B)
          sample.foreach { s =>
            val c = model.encode(s)
            c.angles.zip(dut.io.in.bits.q).foreach { case (v, port) => port.poke(v.U) }
            c.velocities.zip(dut.io.in.bits.qd).foreach { case (v, port) => port.poke(v.S) }
            c.accelerations.zip(dut.io.in.bits.qdd).foreach { case (v, port) => port.poke(v.S) }
          }
          if (!doReset && sample.isDefined && dut.io.in.ready.peek().litToBoolean) {
            val c = model.encode(sample.get).copy(parameters = params.zip(active).toMap)
            taken += ((t, c, sequence))
            sample = None
          }
          if (dut.io.out.valid.peek().litToBoolean)
            outputs += ((
              t,
              ArmOutputCodes(
                dut.io.out.bits.torques.tau.map(_.peek().litValue).toIndexedSeq,
                dut.io.out.bits.torques.outOfRange.map(_.peek().litToBoolean).toIndexedSeq
              ),
              dut.io.out.bits.sequence.peek().litValue.toInt
            ))
          dut.clock.step()
          // Register updates at the edge: a commit takes the staged payload before this cycle's write.
          if (!doReset) {
            if (commit) { active = staged; sequence = (sequence + 1) % seqMod }
            write.foreach { case (k, c) => staged = staged.updated(k, c) }
          }
        }
        // Every sample not cut by a reset leaves exactly `latency` cycles after it was taken.
        val resets = resetAt.toSeq
        val expected = taken.filterNot { case (t, _, _) => resets.exists(r => r >= t && r < t + p.latency) }
        assert(
          outputs.map(_._1) == expected.map(_._1 + p.latency),
          s"outputs at ${outputs.map(_._1).take(8)}, expected at ${expected.map(_._1 + p.latency).take(8)}"
        )
        var worst = 0.0
        var inRange = 0
        expected.zip(outputs).foreach { case ((t, codes, seq), (_, out, outSeq)) =>
          val want = model.evaluate(codes)
          assert(out == want, s"sample taken in cycle $t: RTL $out, model $want")
          assert(outSeq == seq, s"sample taken in cycle $t: sequence $outSeq, committed $seq")
          if (!out.outOfRange.exists(identity)) {
            inRange += 1
            val s = ArmSample(
              codes.angles.map(a => a.toDouble / (BigInt(1) << p.numerics.angleBits).toDouble * 2 * math.Pi),
              codes.velocities.map(p.numerics.velocityPortFormat.toDouble),
              codes.accelerations.map(p.numerics.accelerationPortFormat.toDouble)
            )
            val body = bodyOf(inertial.map(codes.parameters))
            val g = Vec3(Signal.gravity.map(a => port.toDouble(codes.parameters(a))))
            val ref = Rnea.reference(spec.merged(p.chain, body).copy(gravity = g), s.q, s.qd, s.qdd)
            model.torques(out).zip(ref).zipWithIndex.foreach { case ((h, r), j) =>
              assert(math.abs(h - r) <= p.errorBounds(j), s"cycle $t joint ${j + 1}: ${math.abs(h - r)}")
              worst = math.max(worst, math.abs(h - r))
            }
          }
        }
        val commits = expected.map(_._3).distinct.size
        println(
          s"[payload+gravity] UR5 II=${p.schedule.clocksPerSample} memory: ${expected.size} samples bit-exact " +
            s"with the model over $cycles cycles ($commits payload sequence numbers, $inRange in range, " +
            f"worst |hw - merged RNEA| $worst%.3e N·m, bound ${p.errorBound}%.3e), latency ${p.latency}, " +
            s"${p.schedule.multiplierBlocks} multiplier blocks"
        )
        assert(commits >= 3, s"only $commits payloads seen")
        assert(expected.exists(e => inertial.exists(e._2.parameters(_) != 0)), "no sample with a payload")
        val reset = params.zip(PayloadedArm.resetCodes(p)).toMap
        assert(
          expected.exists(e => Signal.gravity.exists(a => e._2.parameters(a) != reset(a))),
          "no sample with a committed gravity"
        )
        assert(expected.exists(_._2.parameters == reset), "no sample with the reset gravity and no payload")
      }
    }

  it should "take the run-time gravity alone (no payload): three registers reset to the elaboration gravity" in {
    val config = ArmGolden.of("ur5").head.config
    val p = Compiler.arm(
      config.copy(
        robot = config.robot.copy(mounting = reducerload.robot.Mounting.ceiling),
        gravity = GravitySettings(runtime = true),
        schedule = ScheduleRequest(clocksPerSample = Some(88), storage = Some(Storage.Memory))
      )
    )
    assert(p.payload.isEmpty && p.numerics.parameters == Signal.gravity)
    // Reset: the ceiling-mounted UR5's folded gravity, (0, 0, +9.81).
    val reset = PayloadedArm.resetCodes(p).map(p.numerics.parameterPortFormat.toDouble)
    assert(reset.zip(Seq(0.0, 0.0, 9.81)).forall { case (a, b) =>
      math.abs(a - b) <= p.numerics.parameterPortFormat.lsb
    })
    val model = new ArmModel(p)
    val s = ArmSample(IndexedSeq.fill(6)(0.3), IndexedSeq.fill(6)(0.1), IndexedSeq.fill(6)(0.2))
    val withReset = model.encode(s).copy(parameters = Signal.gravity.zip(PayloadedArm.resetCodes(p)).toMap)
    assert(model.evaluate(withReset) == model.evaluate(model.encode(s)))
    circt.stage.ChiselStage.convert(new PayloadedArm(p)) // elaborates with three gravity registers
  }
}
