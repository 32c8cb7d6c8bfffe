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
import reducerload.testutil.{ArmGolden, PayloadDesigns, Seeds, SimBackend}

import scala.collection.mutable.ArrayBuffer
import scala.util.Random
import reducerload.testutil.SimBackend.multiplierImpl // the JVM simulator builds the multipliers' Chisel twin

/**
 * A row of a golden payload trace streamed through [[PayloadedArm]]: the sample, the payload it carries and
 * Pinocchio's torques with that payload.
 */
final case class GoldenPayloadRow(sample: ArmSample, payload: RigidBody, torques: IndexedSeq[Double])

object GoldenPayloadRow {

  /**
   * Rows of a robot's golden payload traces (golden/arms/payload/): every `pickEvery`-th row of the
   * pick-and-place trace (each of its six payloads) and the first `random` rows of the random one (no
   * payload, the maximum mass, the centre of mass on the edge, both, and uniform ones).
   */
  def of(robot: String, pickEvery: Int, random: Int): IndexedSeq[GoldenPayloadRow] =
    ArmGolden.withPayload(robot).toIndexedSeq.flatMap { t =>
      val rows = t.samples.indices.map(i => GoldenPayloadRow(t.samples(i), t.payloads(i).get, t.torques(i)))
      if (t.name.endsWith("pick_and_place")) rows.indices.filter(_ % pickEvery == 0).map(rows)
      else rows.take(random)
    }
}

/**
 * The UR5 (with run-time gravity too) and the Panda with a run-time payload at a block-RAM schedule, through
 * their parameter registers, one Verilator design each, every check in one simulation. First rows of the
 * robot's golden payload traces: the host writes each row's payload (between stray writes it never commits)
 * and commits it at a random time before the row's sample; then random payloads and gravity vectors (some
 * beyond the declared sets) written and committed at random times, with two resets. Samples stream with
 * bubbles and back-pressure. Checked cycle by cycle: every sample's torques and flags bit-exact with the
 * model for the parameters committed when it was taken, at exactly the latency, with their sequence number;
 * in-range torques within the derived bound of RNEA with the payload merged into the last body and the
 * committed gravity; the golden rows within each joint's bound and 1e-3 N·m of Pinocchio.
 */
class PayloadedArmSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "PayloadedArm"

  /** Streams `golden` then random samples and payloads through `p`'s PayloadedArm and checks (see above). */
  private def stream(label: String, p: ArmParams, golden: IndexedSeq[GoldenPayloadRow], seed: Long): Unit = {
    val model = new ArmModel(p)
    val params = p.numerics.parameters
    val port = p.numerics.parameterPortFormat
    val rng = new Random(Seeds(s"payloaded-arm-$label", seed))
    def payload(spec: PayloadSpec): RigidBody = {
      val scale = if (rng.nextDouble() < 0.2) 2.5 else 1.0 // some beyond the declared set
      val m = rng.nextDouble() * spec.maxMass * scale
      def coord() = (rng.nextDouble() * 2 - 1) * spec.comRadius * scale / math.sqrt(3)
      val top = m * spec.maxGyrationRadius * spec.maxGyrationRadius * scale
      val d = Vec3(rng.nextDouble() * top, rng.nextDouble() * top, rng.nextDouble() * top) * 0.5
      RigidBody(m, Vec3(coord(), coord(), coord()), Mat3.diagonal(d))
    }
    // A gravity of random direction, mostly within the declared magnitude, some components beyond it.
    def gravity(spec: GravitySpec): Vec3 = {
      val scale = if (rng.nextDouble() < 0.2) 1.6 else 1.0
      val d = Vec3(rng.nextGaussian(), rng.nextGaussian(), rng.nextGaussian())
      d * (rng.nextDouble() * spec.maxMagnitude * scale / d.norm)
    }
    def code(x: Double) = port.fromDouble(x, Rounding.HalfUp)._1
    // The writes of a payload or of a gravity vector, (register index, code) each.
    def writesOf(values: Map[Signal.Parameter, Double]): List[(Int, BigInt)] =
      params.zipWithIndex.collect { case (s, k) if values.contains(s) => (k, code(values(s))) }.toList
    def randomWrites(): List[(Int, BigInt)] =
      (p.payload, p.gravity) match {
        case (Some(s), Some(g)) =>
          if (rng.nextBoolean()) writesOf(s.values(p.chain, payload(s))) else writesOf(g.values(gravity(g)))
        case (Some(s), None) => writesOf(s.values(p.chain, payload(s)))
        case (None, Some(g)) => writesOf(g.values(gravity(g)))
        case (None, None)    => Nil
      }
    val inertial = params.collect { case s: Signal.Inertial => s }
    def bodyOf(codes: IndexedSeq[BigInt]): RigidBody = {
      val v = inertial.map(_.parameter).zip(codes.map(port.toDouble)).toMap
      if (v.isEmpty) RigidBody.massless
      else
        RigidBody(
          v(InertialParameter.Mass),
          Vec3((0 until 3).map(a => v(InertialParameter.Com(a)))),
          Mat3.tabulate((r, c) => v(InertialParameter.Inertia(math.min(r, c), math.max(r, c))))
        )
    }
    // A golden row's registers: its payload, the reset gravity.
    val resetCodes = PayloadedArm.resetCodes(p)
    val goldenCodes = golden.map { row =>
      val v = p.payload.get.values(p.chain, row.payload)
      params.zip(resetCodes).map { case (s, r) => v.get(s).fold(r)(code) }
    }
    val randomCycles = SimBackend.scale(120) * p.schedule.clocksPerSample
    val seqMod = 1 << PayloadedArm.sequenceBits

    test(new PayloadedArm(p)).withAnnotations(SimBackend.annotations) { dut =>
      // The registers' model: staged, active, sequence.
      var staged = resetCodes
      var active = staged
      var sequence = 0
      var writes = List.empty[(Int, BigInt)] // parameters being written, one per cycle
      var sample = Option.empty[(ArmSample, Option[Int])] // offered until taken; golden row index
      var next = 0 // the next golden row
      var randomStart = if (golden.isEmpty) 0 else -1 // the cycle the random part starts
      def resetAt(t: Int) = randomStart >= 0 && (t == randomStart + randomCycles / 3 ||
        t == randomStart + 2 * randomCycles / 3)
      val taken = ArrayBuffer.empty[(Int, SampleCodes, Int, Option[Int])] // cycle, codes, sequence, row
      val outputs = ArrayBuffer.empty[(Int, ArmOutputCodes, Int)]
      val resets = ArrayBuffer.empty[Int]
      var t = 0
      while (randomStart < 0 || t < randomStart + randomCycles + p.latency + 2) {
        assert(t < (golden.size + 8) * 4 * p.schedule.clocksPerSample + randomCycles * 2, s"$label: stuck")
        val doReset = resetAt(t)
        dut.reset.poke(doReset.B)
        if (doReset) {
          staged = resetCodes; active = staged; sequence = 0; writes = Nil
          resets += t
        }
        // Host. Golden part: write the next row's parameters (after any stray write) and commit them at a
        // random time once staged; stray writes of random payloads otherwise, never committed. Random part:
        // random parameters written, commits at random times.
        val commit = !doReset && {
          if (next < golden.size) {
            val want = goldenCodes(next)
            if (writes.isEmpty && active != want && staged != want)
              writes = params.indices.map(k => (k, want(k))).toList
            else if (writes.isEmpty && active == want && rng.nextDouble() < 0.02) writes = randomWrites()
            writes.isEmpty && active != want && staged == want && rng.nextDouble() < 0.3
          } else {
            if (writes.isEmpty && rng.nextDouble() < 0.03) writes = randomWrites()
            rng.nextDouble() < 0.03
          }
        }
        val write = if (doReset) None else writes.headOption
        writes = if (doReset) Nil else writes.drop(1)
        dut.io.host.write.valid.poke(write.isDefined.B)
        write.foreach { case (k, c) =>
          dut.io.host.write.bits.index.poke(k.U)
          dut.io.host.write.bits.value.poke(c.S)
        }
        dut.io.host.commit.poke(commit.B)
        // Samples: offered with bubbles, held until taken; a golden row once its payload is the active one.
        if (sample.isEmpty && !doReset && rng.nextDouble() < 0.5) {
          if (next < golden.size) {
            if (active == goldenCodes(next) && !commit) sample = Some((golden(next).sample, Some(next)))
          } else if (t < randomStart + randomCycles) {
            val (q, qd, qdd) =
              RandomChains.sample(rng, p.maxVelocity.map(_ * 1.05), p.maxAcceleration.map(_ * 1.05))
            sample = Some((ArmSample(q, qd, qdd), None))
          }
        }
        dut.io.in.valid.poke((sample.isDefined && !doReset).B)
        sample.foreach { case (s, _) =>
          val c = model.encode(s)
          c.angles.zip(dut.io.in.bits.q).foreach { case (v, port) => port.poke(v.U) }
          c.velocities.zip(dut.io.in.bits.qd).foreach { case (v, port) => port.poke(v.S) }
          c.accelerations.zip(dut.io.in.bits.qdd).foreach { case (v, port) => port.poke(v.S) }
        }
        if (!doReset && sample.isDefined && dut.io.in.ready.peek().litToBoolean) {
          val (s, row) = sample.get
          taken += ((t, model.encode(s).copy(parameters = params.zip(active).toMap), sequence, row))
          sample = None
          if (row.isDefined) {
            next += 1
            if (next == golden.size) randomStart = t + 1
          }
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
        // Register updates at the edge: a commit takes the staged parameters before this cycle's write.
        if (!doReset) {
          if (commit) { active = staged; sequence = (sequence + 1) % seqMod }
          write.foreach { case (k, c) => staged = staged.updated(k, c) }
        }
        t += 1
      }
      // Every sample not cut by a reset leaves exactly `latency` cycles after it was taken.
      val expected = taken.filterNot { case (t, _, _, _) => resets.exists(r => r >= t && r < t + p.latency) }
      assert(
        outputs.map(_._1) == expected.map(_._1 + p.latency),
        s"$label: outputs at ${outputs.map(_._1).take(8)}, expected at ${expected.map(_._1 + p.latency).take(8)}"
      )
      var worst = 0.0
      var inRange = 0
      val worstPinocchio = Array.fill(p.chain.size)(0.0)
      expected.zip(outputs).foreach { case ((t, codes, seq, row), (_, out, outSeq)) =>
        val want = model.evaluate(codes)
        assert(out == want, s"$label: sample taken in cycle $t: RTL $out, model $want")
        assert(outSeq == seq, s"$label: sample taken in cycle $t: sequence $outSeq, committed $seq")
        if (!out.outOfRange.exists(identity)) {
          inRange += 1
          val s = ArmSample(
            codes.angles.map(a => a.toDouble / (BigInt(1) << p.numerics.angleBits).toDouble * 2 * math.Pi),
            codes.velocities.map(p.numerics.velocityPortFormat.toDouble),
            codes.accelerations.map(p.numerics.accelerationPortFormat.toDouble)
          )
          val body = bodyOf(inertial.map(codes.parameters))
          val g =
            if (p.gravity.isDefined) Vec3(Signal.gravity.map(a => port.toDouble(codes.parameters(a))))
            else p.chain.gravity
          val chain = p.payload.fold(p.chain)(_.merged(p.chain, body)).copy(gravity = g)
          val ref = Rnea.reference(chain, s.q, s.qd, s.qdd)
          model.torques(out).zip(ref).zipWithIndex.foreach { case ((h, r), j) =>
            assert(
              math.abs(h - r) <= p.errorBounds(j),
              s"$label: cycle $t joint ${j + 1}: ${math.abs(h - r)}"
            )
            worst = math.max(worst, math.abs(h - r))
          }
        }
        row.foreach { i =>
          assert(!out.outOfRange.exists(identity), s"$label: golden row $i flagged")
          assert(
            codes.parameters == params.zip(goldenCodes(i)).toMap,
            s"$label: golden row $i with another payload"
          )
          model.torques(out).zip(golden(i).torques).zipWithIndex.foreach { case ((h, pin), j) =>
            val e = math.abs(h - pin)
            assert(
              e <= p.errorBounds(j) + 1e-9 && e <= ArmChecks.target,
              s"$label: golden row $i joint ${j + 1}: $e"
            )
            worstPinocchio(j) = math.max(worstPinocchio(j), e)
          }
        }
      }
      val rows = expected.count(_._4.isDefined)
      assert(rows == golden.size, s"$label: $rows of ${golden.size} golden rows came out")
      val commits = expected.map(_._3).distinct.size
      println(
        s"[payload] $label II=${p.schedule.clocksPerSample}: ${expected.size} samples " +
          s"bit-exact with the model over $t cycles (${golden.size} golden rows, $commits sequence numbers, " +
          f"$inRange in range, worst |hw - merged RNEA| $worst%.3e N·m, bound ${p.errorBound}%.3e), latency " +
          s"${p.latency}, ${p.schedule.multiplierBlocks} multiplier blocks"
      )
      p.chain.joints.indices.foreach { j =>
        println(
          f"[payload] $label ${p.jointNames(j)}%-22s golden rows: max |hw - pinocchio| ${worstPinocchio(j)}%.3e N·m " +
            f"(bound ${p.errorBounds(j)}%.3e)"
        )
      }
      assert(commits >= 3, s"$label: only $commits payloads seen")
      assert(
        expected.exists(e => inertial.exists(e._2.parameters(_) != 0)),
        s"$label: no sample with a payload"
      )
      if (p.gravity.isDefined) {
        val reset = params.zip(resetCodes).toMap
        assert(
          expected.exists(e => Signal.gravity.exists(a => e._2.parameters(a) != reset(a))),
          s"$label: no sample with a committed gravity"
        )
        assert(expected.exists(_._2.parameters == reset), s"$label: no sample with the reset parameters")
      }
    }
  }

  /** Rows of the golden payload traces: all of the chosen ones on Verilator, fewer on the JVM simulator. */
  private def goldenRows(robot: String, pickEvery: Int, random: Int): IndexedSeq[GoldenPayloadRow] = {
    val rows = GoldenPayloadRow.of(robot, pickEvery, random)
    if (SimBackend.isVerilator) rows else rows.indices.filter(_ % 10 == 0).map(rows)
  }

  it should "compute every UR5 sample with the payload and gravity committed when it was taken, bit-exact " +
    "with the model, and say which" in {
      val p = Compiler.arm(PayloadDesigns.ur5)
      stream("ur5", p, goldenRows("ur5", pickEvery = 10, random = 20), 3105L)
    }

  it should "compute every Panda sample with the payload committed when it was taken, bit-exact with the " +
    "model, within each joint's bound and 1e-3 N·m of Pinocchio" in {
      // The Panda's device fit with the payload (EP4CE30): 121 clocks per sample, values in block RAM.
      val p = Compiler.arm(
        ArmGolden
          .of("panda")
          .head
          .config
          .copy(
            payload = PayloadSettings(enabled = true, maxMass = 3.0),
            schedule = ScheduleRequest(clocksPerSample = Some(121), storage = Some(Storage.Memory))
          )
      )
      stream("panda", p, goldenRows("panda", pickEvery = 6, random = 40), 3107L)
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
