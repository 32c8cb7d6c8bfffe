package reducerload.regmap

import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.arm.{ArmModel, ArmSample}
import reducerload.dynamics.RandomChains
import reducerload.monitor.{JointField, RegisterKey}
import reducerload.robot.{Mat3, Vec3}
import reducerload.testutil.{Scratch, Seeds, SimBackend}
import reducerload.testutil.SimBackend.multiplierImpl

import scala.util.Random

/** What the C program must print, from the models and the description (never from the driver). */
object CDriverExpect {

  /**
   * Every monitor figure of the snapshot in SI units (torques N m, speeds rad/s) or counts, by result key.
   */
  def monitor(
      c: reducerload.compiler.Compiled,
      bank: IndexedSeq[BigInt]
  ): Map[String, Either[BigInt, Double]] = {
    val m = c.monitor.get
    val values = m.registerMap.decode(bank)
    (0 until m.joints).flatMap { j =>
      val torque = m.torqueFormats(j)
      val speed = m.velocityFormats(j)
      DriverLayout.figures(m.histogramBins(j)).map { f =>
        val v = values(RegisterKey.Joint(j, f))
        val si: Either[BigInt, Double] = f match {
          case JointField.PeakTorque | JointField.MinTorque | JointField.LastEventPeak =>
            Right(torque.toDouble(v))
          case JointField.LastEventSpeed | JointField.SpeedSum => Right(speed.toDouble(v))
          case JointField.DamageSum                            => Right(v.toDouble)
          case _                                               => Left(v)
        }
        s"j${j + 1}.${f.name}" -> si
      }
    }.toMap + ("snapshot_count" -> Left(values(RegisterKey.SnapshotCount)))
  }

  /** The inertia of ABB load data about its cog in the payload frame: R diag(ix, iy, iz) R^T. */
  def abbInertia(axis: Vec3, angle: Double, principal: Vec3): Seq[Double] = {
    val r = Mat3.axisAngle(axis, angle)
    val i = r * Mat3.diagonal(principal) * r.transpose
    Seq(i(0, 0), i(0, 1), i(0, 2), i(1, 1), i(1, 2), i(2, 2))
  }
}

/**
 * The C program against a live register bus of any design (any DUT, or [[RegisterFileModel]]): the
 * identification, a payload written from SI units, committed and read back (when the design has a run-time
 * payload), and one sample through the register-driven sample mode, each against the models. Reusable inside
 * another simulation: give it the DUT's word read and write.
 */
object CDriverScenario {
  def run(
      c: reducerload.compiler.Compiled,
      exe: java.nio.file.Path,
      read: Int => BigInt,
      write: (Int, BigInt) => Unit,
      seed: Long
  ): BfmRun = {
    val rnd = new Random(seed)
    val n = c.arm.numerics
    val model = new ArmModel(c.arm)
    val port = if (n.parameters.isEmpty) None else Some(n.parameterPortFormat)
    val payloaded = n.parameters.exists(s => DriverLayout.parameterIndexName(c, s).contains("RL_PARAM_MASS"))
    def within(r: Double) = (rnd.nextDouble() * 2 - 1) * r
    val box = c.config.payload
    val r = box.comRadius
    val i = box.maxMass * box.maxGyrationRadius * box.maxGyrationRadius
    val si = Seq(rnd.nextDouble() * box.maxMass, within(r), within(r), within(r), rnd.nextDouble() * i) ++
      Seq(within(i), within(i), rnd.nextDouble() * i, within(i), rnd.nextDouble() * i)
    val (q, qd, qdd) =
      RandomChains.sample(rnd, c.arm.maxVelocity.map(_ * 0.9), c.arm.maxAcceleration.map(_ * 0.9))
    val args = (if (payloaded) "payload" +: si.map(_.toString) else Nil) ++
      ("sample" +: (q ++ qd ++ qdd).map(_.toString))
    val run = new BusFunctionalModel(read, write).serve(exe.toString +: args)
    assert(
      run.exit == 0 && run("init") == "0",
      s"exit ${run.exit}, init ${run.results.get("init")}: ${run.errors}"
    )
    val body =
      if (payloaded) reducerload.arm.PayloadColumns.body(si) else reducerload.robot.RigidBody.massless
    if (payloaded) {
      val f = port.get
      def staged(v: Double) = f.toDouble(f.quantize(v, reducerload.fixedpoint.Rounding.HalfUp))
      Seq("payload.write", "payload.commit").foreach(k => assert(run(k) == "0", k))
      assert(run("payload.sequence_step") == "1", "the commit steps the sequence by one")
      val keys = Seq("mass") ++ (0 until 3).map(k => s"com$k") ++ (0 until 6).map(k => s"inertia$k")
      keys.zip(si).foreach { case (k, v) => assert(run(s"payload.$k").toDouble == staged(v), s"payload $k") }
    }
    val out = model.evaluate(model.encode(ArmSample(q, qd, qdd), body, c.arm.chain.gravity))
    assert(run("sample") == "0", "sample mode")
    out.tau.zipWithIndex.foreach { case (t, j) =>
      val want = c.arm.analysis.outputPortFormat.toDouble(t)
      assert(
        run(s"sample.tau${j + 1}").toDouble == want,
        s"joint ${j + 1}: C ${run(s"sample.tau${j + 1}")}, model $want"
      )
    }
    assert(BigInt(run("sample.out_of_range")) == out.outOfRange.zipWithIndex.collect { case (true, j) =>
      BigInt(1) << j
    }.sum)
    run
  }
}

/**
 * The C driver (driver/reducer_load.c) compiled with gcc -std=c99 -Wall -Wextra -Werror -pedantic against the
 * monitored planar arm's generated headers, run against the RTL (the `reducer_load` Avalon wrapper on
 * Verilator or the JVM simulator) through [[BusFunctionalModel]]: driver calls -> bus requests -> Avalon-MM
 * transactions. The identification check, a monitor snapshot after seeded samples against MonitorModel fed by
 * ArmModel, torque codes against FixedFormat; the ABB load-data conversion against a rotation built another
 * way; the sample mode through the datapath. The planar arm has no run-time payload (the driver must say
 * RL_ERR_UNSUPPORTED): the payload round trip runs on the UR5's register-file model, and [[CDriverScenario]]
 * inside another simulation.
 */
class CDriverSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "the C driver"

  private val unsupported = "-9"
  private val command = "CDriverSpec"

  private def program(c: reducerload.compiler.Compiled = RegMapDesign.compiled): java.nio.file.Path = {
    if (!CProgram.available) println("CDriverSpec: gcc is not installed: the C driver tests are skipped")
    assume(CProgram.available, "gcc is not installed")
    CDriver.buildTestProgram(Scratch.dir("c-driver-"), c, command)
  }

  it should "refuse a core of another design, and convert ABB load data and torque codes, with no RTL" in {
    val exe = program()
    val map = RegMapDesign.map
    val constants = map.registers.map(r => r.word -> r.register.reset).toMap
    def fakeBus(changed: (String, BigInt)*) = {
      val values = constants ++ changed.map { case (n, v) => map.register(n).word -> v }
      new BusFunctionalModel(w => values.getOrElse(w, BigInt(0)), (_, _) => ())
    }
    assert(fakeBus().serve(Seq(exe.toString)).apply("init") == "0")
    val hash = constants(map.register("id_design_hash").word)
    val cases = Seq(
      "id_magic" -> BigInt(0x12345678) -> "-2",
      "id_version" -> (constants(map.register("id_version").word) + 1) -> "-3",
      "id_design_hash" -> (hash ^ 1) -> "-4",
      "id_shape" -> (constants(map.register("id_shape").word) + 1) -> "-5",
      "id_tau_format" -> (constants(map.register("id_tau_format").word) + 1) -> "-5"
    )
    cases.foreach { case ((reg, value), status) =>
      val run = fakeBus(reg -> value).serve(Seq(exe.toString))
      assert(run("init") == status && run.exit == 1, s"$reg = $value: init ${run("init")}, expected $status")
    }

    val seed = Seeds("CDriverSpec conversions", 32)
    val rnd = new Random(seed)
    val tau = RegMapDesign.compiled.arm.analysis.outputPortFormat
    val codes = Seq(tau.minRaw, tau.maxRaw, BigInt(0), BigInt(-1)) ++
      Seq.fill(20)(BigInt(tau.width, rnd.self) + tau.minRaw)
    val axis = Vec3(rnd.nextGaussian(), rnd.nextGaussian(), rnd.nextGaussian())
    val unit = axis * (1 / axis.norm)
    val angle = rnd.nextDouble() * 2 * math.Pi
    val principal = Vec3(0.01 + rnd.nextDouble(), 0.01 + rnd.nextDouble(), 0.01 + rnd.nextDouble())
    val cog = Vec3(rnd.nextDouble() * 100 - 50, rnd.nextDouble() * 100 - 50, rnd.nextDouble() * 100)
    val quaternion = Seq(math.cos(angle / 2)) ++ (unit * math.sin(angle / 2)).toSeq
    val abb = Seq(3.5) ++ cog.toSeq ++ quaternion ++ principal.toSeq
    val run = fakeBus().serve(
      Seq(exe.toString) ++ codes.flatMap(c => Seq("torque", c.toString)) ++ ("abb" +: abb.map(d => s"$d"))
    )
    assert(run.exit == 0, run.errors)
    codes.foreach(c => assert(run(s"torque.$c").toDouble == tau.toDouble(c), s"torque code $c"))
    val inertia = CDriverExpect.abbInertia(unit, angle, principal)
    inertia.indices.foreach { k =>
      val got = run(s"abb_si.inertia$k").toDouble
      assert(math.abs(got - inertia(k)) <= 1e-12, s"inertia $k: C $got, rotation ${inertia(k)}")
    }
    cog.toSeq.indices.foreach(k =>
      assert(math.abs(run(s"abb_si.com$k").toDouble - cog.toSeq(k) / 1000) <= 1e-15)
    )
    assert(run("abb.write") == unsupported, "the payload block is reserved in this map")
    println(
      s"[c driver] seed $seed: ${codes.size} torque codes exact, ABB inertia within 1e-12 of R diag R^T"
    )
  }

  it should "write a payload from SI units and from ABB load data, commit it, read it back, refuse one beyond the declared set" in {
    val c = ReducerLoadTopDesigns.ur5Payloaded
    val exe = program(c)
    val map = ReducerLoadRegisters(c)
    val n = c.arm.numerics
    val port = n.parameterPortFormat
    def staged(v: Double) = port.toDouble(port.quantize(v, reducerload.fixedpoint.Rounding.HalfUp))
    val seed = Seeds("CDriverSpec payload", 32)
    val rnd = new Random(seed)
    def within(r: Double) = (rnd.nextDouble() * 2 - 1) * r
    val si = Seq(
      0.5 + rnd.nextDouble() * 4,
      within(0.1),
      within(0.1),
      within(0.1),
      0.001 + rnd.nextDouble() * 0.04
    ) ++
      Seq(
        within(0.01),
        within(0.01),
        0.001 + rnd.nextDouble() * 0.04,
        within(0.01),
        0.001 + rnd.nextDouble() * 0.04
      )
    val axis = Vec3(rnd.nextGaussian(), rnd.nextGaussian(), rnd.nextGaussian())
    val unit = axis * (1 / axis.norm)
    val angle = rnd.nextDouble() * 2 * math.Pi
    val principal =
      Vec3(0.002 + rnd.nextDouble() * 0.03, 0.002 + rnd.nextDouble() * 0.03, 0.002 + rnd.nextDouble() * 0.03)
    val cog = Vec3(within(90), within(90), within(90))
    val abb = Seq(2.0) ++ cog.toSeq ++ (Seq(math.cos(angle / 2)) ++ (unit * math.sin(
      angle / 2
    )).toSeq) ++ principal.toSeq
    val file = new RegisterFileModel(map)
    val bfm = new BusFunctionalModel(file.read, file.write)
    val run =
      bfm.serve(Seq(exe.toString) ++ ("payload" +: si.map(_.toString)) ++ ("abb" +: abb.map(_.toString)))
    assert(run.exit == 0 && run("init") == "0", run.errors)
    val keys = Seq("mass") ++ (0 until 3).map(k => s"com$k") ++ (0 until 6).map(k => s"inertia$k")
    Seq("payload.write", "payload.commit", "abb.write", "abb.commit").foreach(k => assert(run(k) == "0", k))
    assert(run("payload.sequence_step") == "1" && run("abb.sequence_step") == "1")
    keys.zip(si).foreach { case (k, v) => assert(run(s"payload.$k").toDouble == staged(v), s"payload $k") }
    val abbSi = Seq(2.0) ++ cog.toSeq.map(_ / 1000) ++ CDriverExpect.abbInertia(unit, angle, principal)
    keys.zip(abbSi).foreach { case (k, v) =>
      val got = run(s"abb.$k").toDouble
      assert(math.abs(got - staged(v)) <= port.lsb, s"abb $k: staged $got, expected ${staged(v)}")
    }
    // Beyond the declared set (max-mass 5 kg): refused, nothing written, the staged payload unchanged.
    val refused = new BusFunctionalModel(file.read, file.write)
      .serve(
        Seq(exe.toString, "refuse", "5.5") ++ si.drop(1).map(_.toString) ++ Seq("refuse", "nan") ++ si
          .drop(1)
          .map(_.toString)
      )
    assert(refused.writes == 0, "a refused payload wrote registers")
    assert(refused("refuse.write") == "-7" || refused("refuse.write") == "-6")
    val first = new BusFunctionalModel(file.read, file.write)
      .serve(Seq(exe.toString, "refuse", "5.5") ++ si.drop(1).map(_.toString))
    assert(first("refuse.write") == "-6", "a 5.5 kg payload with max-mass 5")
    println(
      s"[c driver] seed $seed: payload staged as the port format rounds it, ABB load data within 1 code, 5.5 kg refused"
    )
  }

  it should "run the scenario for another simulation (payload round trip, sample mode) on a register-file model" in {
    val c = ReducerLoadTopDesigns.ur5Payloaded
    val exe = program(c)
    val model = new ArmModel(c.arm)
    val params = c.arm.numerics.parameters
    val file = new RegisterFileModel(
      ReducerLoadRegisters(c),
      Some((codes, committed) => model.evaluate(codes.copy(parameters = params.zip(committed).toMap)))
    )
    val seed = Seeds("CDriverSpec scenario", 32)
    val run = CDriverScenario.run(c, exe, file.read, file.write, seed)
    println(
      s"[c driver] seed $seed: scenario on the UR5's register-file model: ${run.reads} reads, ${run.writes} writes"
    )
  }

  it should "check the identification and read a monitor snapshot in SI units through Avalon-MM as the models say" in {
    val exe = program()
    val c = RegMapDesign.compiled
    val map = RegMapDesign.map
    val seed = Seeds("CDriverSpec monitor", 32)
    val rng = new Random(seed)
    val model = new ArmModel(c.arm)
    val samples = AvalonCsrExpect.samples(c, rng, SimBackend.scale(200))(i => if (i % 20 == 3) 1.3 else 0.97)
    val codes = samples.map(model.encode)
    val expected = CDriverExpect.monitor(c, AvalonCsrExpect.monitorBank(c, codes))
    assert(expected("j1.samples") != Left(BigInt(0)), "the stream must reach the monitor")
    val independent = AvalonCsrExpect.independent(c.monitor.get.joints)
    test(new ReducerLoadAvalon(c.arm, c.monitor, map, "reducer_load"))
      .withAnnotations(SimBackend.annotations) { dut =>
        dut.clock.setTimeout(0)
        val bus = CsrBus.avalon(dut)
        bus.step(1)
        bus.stream(codes)
        bus.step(c.arm.latency + 2)
        val payload = Seq("1", "0", "0", "0.01", "0.001", "0", "0", "0.001", "0", "0.001")
        val run = new BusFunctionalModel(bus.read, bus.write)
          .serve(Seq(exe.toString, "snapshot") ++ ("payload" +: payload))
        assert(run.exit == 0, s"exit ${run.exit}: ${run.errors}")
        assert(run("init") == "0")
        assert(BigInt(run("id.magic")) == independent("id_magic"))
        assert(BigInt(run("id.version")) == independent("id_version"))
        assert(BigInt(run("id.joints")) == independent("id_shape"))
        assert(BigInt(run("id.design_hash")) == ReducerLoadRegisters.designHash(c))
        assert(run("snapshot") == "0")
        val wrong = expected.toSeq.sortBy(_._1).flatMap { case (key, want) =>
          val got = run(key)
          val ok = want match {
            case Left(count) => BigInt(got) == count
            case Right(si) if key.endsWith("damage_sum") =>
              math.abs(got.toDouble - si) <= 1e-15 * math.abs(si)
            case Right(si) => got.toDouble == si
          }
          if (ok) None else Some(s"$key: C $got, model $want")
        }
        assert(wrong.isEmpty, wrong.mkString("; "))
        assert(run("payload.write") == unsupported, "the payload block is reserved in this map")
        println(
          s"[c driver] seed $seed: ${codes.size} samples, ${expected.size} monitor figures equal, " +
            s"${run.reads} reads and ${run.writes} writes through the bus"
        )
        // The register-driven sample mode on the same RTL, through the datapath, against ArmModel.
        val sampleRun = CDriverScenario.run(c, exe, bus.read, bus.write, seed)
        println(
          s"[c driver] seed $seed: sample mode on reducer_load (Avalon-MM): ${sampleRun("sample.tau1")} N.m"
        )
      }
  }
}
