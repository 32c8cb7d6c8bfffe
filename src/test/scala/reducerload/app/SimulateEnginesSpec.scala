package reducerload.app

import reducerload.testutil.CompiledParams
import reducerload.testutil.Scratch
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.arm.{ArmDatapath, ArmModel, ArmOutputCodes, ArmSample, ArmTrajectory, LoadReference}
import reducerload.compiler.Compiler
import reducerload.config.LoadParams
import reducerload.dynamics.{RandomChains, Rnea}
import reducerload.load._
import reducerload.sim.rtl.{ArmDriver, Cycle}
import reducerload.sim.text.{DoubleText, FixedDecimal}
import reducerload.testutil.{monitoredPlanar3, ArmGolden, Golden, Seeds, SimBackend}

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}
import scala.collection.mutable.ArrayBuffer
import scala.sys.process._
import scala.util.{Random, Try}
import reducerload.testutil.SimBackend.multiplierImpl // the JVM simulator builds the multipliers' Chisel twin

/**
 * `run simulate` end to end on the golden traces plus rows beyond the declared ranges (--saturate): the RTL
 * harness with one and two jobs, and the model engine, write the same file, byte for byte, as the chiseltest
 * peek/poke path (joint 3) or the bit-accurate model (the arm; the RTL equals the model in ArmDatapathSpec),
 * with the reference conversions (BigDecimal) of the model; the hardware's values in the one text of a code,
 * [[FixedDecimal]], checked to read back as the model's doubles.
 */
class SimulateEnginesSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "simulate's engines"

  private def verilatorPresent: Boolean = Try(
    Seq("verilator", "--version").!!(ProcessLogger(_ => ()))
  ).isSuccess

  private def csv(header: Seq[String], rows: Seq[Seq[Double]]): Path = {
    val f = Scratch.file("engines-", ".csv")
    Files.write(
      f,
      (header.mkString(",") +: rows.map(_.mkString(",")))
        .mkString("", "\n", "\n")
        .getBytes(StandardCharsets.UTF_8)
    )
    f
  }

  /** `run simulate` on `input` with `args`: the output file's text. */
  private def simulate(input: Path, args: String*): String = {
    val out = Scratch.dir("engines-out-").resolve("out.csv")
    Main.run(Seq("simulate", "--input", input.toString, "--output", out.toString) ++ args)
    new String(Files.readAllBytes(out), StandardCharsets.UTF_8)
  }

  private def file(header: String, lines: Seq[String]): String = (header +: lines).mkString("", "\n", "\n")

  /**
   * The golden traces, out-of-range rows, values beyond the port formats, and exact rounding ties of the
   * input codes.
   */
  private def jointSamples(p: LoadParams, rng: Random): IndexedSeq[ArmSample] = {
    val tie = 1 + math.scalb(1.0, -p.datapath.velocityFracBits - 1)
    Golden.all.flatMap(_.samples).toIndexedSeq ++ IndexedSeq.fill(200)(
      LoadChecks.outOfRangeSample(p.robot, rng)
    ) ++ IndexedSeq(
      ArmSample.fromRow(Seq(0.1, 0.2, 0.3, 1e6, -1e6, 0, 1e7, -1e7, 0)),
      ArmSample.fromRow(Seq(tie, -tie, tie, tie, -tie, tie, tie, -tie, tie))
    )
  }

  /** The joint-3 file the old simulate wrote from RTL outputs: BigDecimal conversions of the model. */
  private def jointFile(
      p: LoadParams,
      samples: IndexedSeq[ArmSample],
      outs: IndexedSeq[ArmOutputCodes]
  ): String = {
    val model = new LoadChecks.Joint3Model(p)
    assert(outs.size == samples.size)
    file(
      "idx,load_hw,load_ref,error,out_of_range",
      samples.indices.map { i =>
        val hw = model.loadOf(outs(i))
        val ref = LoadReference.torque(p.robot, p.model, samples(i))
        // The hardware's value as the one result-file text of a code (FixedDecimal), which must read back as the model's load.
        val hwText = FixedDecimal.format(outs(i).tau(0), p.arm.analysis.outputPortFormat.fracBits)
        assert(hwText.toDouble == hw, s"sample $i: $hwText is not the model's load $hw")
        s"$i,$hwText,${DoubleText.format(ref)},${DoubleText
            .format(hw - ref)},${if (outs(i).outOfRange.exists(identity)) 1 else 0}"
      }
    )
  }

  it should "write the chiseltest path's file from the harness (--jobs 1 and 2) and the model (default design)" in {
    assume(verilatorPresent, "verilator is not installed")
    val p = LoadParams.default
    val samples = jointSamples(p, new Random(Seeds("simulate-engines-default", 51L)))
    val model = new LoadChecks.Joint3Model(p)
    val observed = ArrayBuffer.empty[ArmOutputCodes]
    test(new ArmDatapath(p.arm)).withAnnotations(SimBackend.annotations) { dut =>
      val stimulus = samples.iterator.map(s => Cycle.Sample(model.encode(s))) ++ Iterator.fill(
        p.arm.latency + 1
      )(Cycle.Bubble)
      ArmDriver.run(dut, stimulus, (_, out) => out.foreach(observed += _), holdUntilReady = true)
    }
    val expected = jointFile(p, samples, observed.toIndexedSeq)
    assert(expected.linesIterator.count(_.endsWith(",1")) >= 200, "too few rows flagged out of range")
    val input = csv(Joint3Columns.names, samples.map(_.toSeq))
    Seq(Seq("--jobs", "1"), Seq("--jobs", "2"), Seq("--engine", "model", "--jobs", "2")).foreach { args =>
      assert(
        simulate(input, "--saturate" +: args: _*) == expected,
        s"simulate ${args.mkString(" ")} wrote another file"
      )
    }
  }

  it should "wait for ready with a shared CORDIC unit: the harness writes the model's file (compact preset)" in {
    assume(verilatorPresent, "verilator is not installed")
    val p = LoadParams.compact
    assert(p.arm.schedule.clocksPerSample > 1, "the compact preset no longer shares the CORDIC unit")
    val samples = jointSamples(p, new Random(Seeds("simulate-engines-compact", 52L)))
    val model = new LoadChecks.Joint3Model(p)
    val expected = jointFile(p, samples, samples.map(s => model.evaluate(model.encode(s))))
    val input = csv(Joint3Columns.names, samples.map(_.toSeq))
    Seq(Seq("--jobs", "2"), Seq("--engine", "model", "--jobs", "1")).foreach { args =>
      assert(
        simulate(input, Seq("--preset", "compact", "--saturate") ++ args: _*) == expected,
        s"simulate ${args.mkString(" ")} wrote another file"
      )
    }
  }

  /**
   * The arm file `run simulate` must write for `design`, from the bit-accurate model and the double
   * reference: `robot`'s golden samples, seeded random ones within the declared ranges, and rows with one
   * velocity or acceleration beyond its range (flagged).
   */
  private def armCase(robot: String, design: Seq[String], seed: Long): (Path, String) = {
    val arm = Compiler.arm(Cli.parse("simulate", design, Simulate.options, Simulate.flags).params)
    val n = arm.chain.size
    val rng = new Random(Seeds(s"simulate-engines-$robot", seed))
    val golden = ArmGolden.of(robot).flatMap(_.samples).toIndexedSeq
    val beyond = IndexedSeq.fill(100) {
      val j = rng.nextInt(n)
      val s = golden(rng.nextInt(golden.size))
      if (rng.nextBoolean()) s.copy(qd = s.qd.updated(j, -1.5 * arm.maxVelocity(j)))
      else s.copy(qdd = s.qdd.updated(j, 1.5 * arm.maxAcceleration(j)))
    }
    val random = IndexedSeq.fill(200) {
      val (q, qd, qdd) = RandomChains.sample(rng, arm.maxVelocity, arm.maxAcceleration)
      ArmSample(q, qd, qdd)
    }
    val samples = golden ++ beyond ++ random
    val model = new ArmModel(arm)
    val expected = file(
      ("idx" +: (1 to n).flatMap(j => Seq(s"tau${j}_hw", s"tau${j}_ref", s"tau${j}_error")) :+ "out_of_range")
        .mkString(","),
      samples.indices.map { i =>
        val s = samples(i)
        val out = model.evaluate(model.encode(s))
        val (hw, ref) = (model.torques(out), Rnea.reference(arm.chain, s.q, s.qd, s.qdd))
        val hwText = out.tau.map(FixedDecimal.format(_, arm.analysis.outputPortFormat.fracBits))
        assert(
          (0 until n).forall(j => hwText(j).toDouble == hw(j)),
          s"sample $i: ${hwText.mkString(",")} are not the model's torques"
        )
        (i.toString +: (0 until n).flatMap(j =>
          Seq(hwText(j), DoubleText.format(ref(j)), DoubleText.format(hw(j) - ref(j)))
        ) :+
          (if (out.outOfRange.exists(identity)) "1" else "0")).mkString(",")
      }
    )
    assert(expected.linesIterator.count(_.endsWith(",1")) >= 100)
    (csv(ArmTrajectory.columns(n), samples.map(s => s.q ++ s.qd ++ s.qdd)), expected)
  }

  it should "write the model's file for every joint of the planar arm from the harness (--jobs 2, one sample per clock or per 7) and the model" in {
    assume(verilatorPresent, "verilator is not installed")
    val design = Seq("--robot", "planar3")
    val (input, expected) = armCase("planar3", design, 53L)
    // A shared schedule changes when results come, not what they are: the harness waits for ready.
    Seq(
      Seq("--jobs", "2"),
      Seq("--engine", "model", "--jobs", "1"),
      Seq("--clocks-per-sample", "7", "--schedule.cordic-units", "1", "--jobs", "2")
    ).foreach { args =>
      assert(
        simulate(input, design ++ Seq("--saturate") ++ args: _*) == expected,
        s"simulate ${args.mkString(" ")} wrote another file"
      )
    }
  }

  it should "write the model's file for the planar arm with its reducer monitor from the harness (host inputs held at 0)" in {
    assume(verilatorPresent, "verilator is not installed")
    val design = Seq("--robot", "planar3")
    val (input, expected) = armCase("planar3", design, 53L)
    // The emitted top is MonitoredArm: its io_host_* inputs are not the harness's to drive.
    assert(
      simulate(
        input,
        monitoredPlanar3 ++ Seq(
          "--saturate",
          "--jobs",
          "1"
        ): _*
      ) == expected
    )
  }

  // The harness runs the Verilog `run emit` writes (firtool); the chiseltest suites run another
  // compiler's. A read the memory schedule left undefined came out right in one and wrong in the other.
  it should "write the model's file for every joint of the UR5 with block-RAM banks (64 and 88 clocks, 1e-3 N·m) from the emitted Verilog" in {
    assume(verilatorPresent, "verilator is not installed")
    Seq(64 -> 54L, 88 -> 55L).foreach { case (clocks, seed) =>
      val design = Seq(
        "--robot",
        "golden/robots/ur5_robot.urdf",
        "--tip",
        "tool0",
        "--max-acceleration",
        "15",
        "--target-error",
        "1e-3",
        "--clocks-per-sample",
        clocks.toString,
        "--schedule.storage",
        "memory"
      )
      val (input, expected) = armCase("ur5", design, seed)
      assert(
        simulate(input, design ++ Seq("--saturate", "--jobs", "2"): _*) == expected,
        s"simulate at $clocks clocks wrote another file"
      )
    }
  }

  it should "write the model's file for every joint of the Panda with block-RAM banks (114 clocks, 1e-3 N·m: issue 12's Panda design) from the emitted Verilog" in {
    assume(verilatorPresent, "verilator is not installed")
    val design = Seq(
      "--robot",
      "golden/robots/panda.urdf",
      "--tip",
      "panda_hand",
      "--max-acceleration",
      "[15,7.5,10,12.5,15,20,20]",
      "--target-error",
      "1e-3",
      "--clocks-per-sample",
      "114",
      "--schedule.storage",
      "memory"
    )
    val (input, expected) = armCase("panda", design, 57L)
    assert(
      simulate(input, design ++ Seq("--saturate", "--jobs", "2"): _*) == expected,
      "simulate wrote another file"
    )
  }
}
