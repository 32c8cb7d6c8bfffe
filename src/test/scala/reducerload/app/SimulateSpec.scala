package reducerload.app

import reducerload.arm.PayloadColumns
import reducerload.sim.replay.ReplayColumns
import reducerload.testutil.{CompiledParams, PayloadDesigns}
import reducerload.testutil.Scratch
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.testutil.Seeds
import reducerload.util.InputError

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}
import scala.sys.process._
import scala.util.{Random, Try}

class SimulateSpec extends AnyFlatSpec {
  behavior of "simulate"

  private val header = "t1,t2,t3,d1,d2,d3,dd1,dd2,dd3"
  private val good = "0.1,0.2,0.3,1,-1,0.5,2,3,-4"

  private def file(content: Array[Byte]): Path = {
    val f = Scratch.file("traj-", ".csv")
    Files.write(f, content)
    f
  }
  private def text(s: String) = file(s.getBytes(StandardCharsets.UTF_8))

  /** A malformed input: one line naming the file, a non-zero exit (InputError), and no output file. */
  private def refused(input: Path, words: String*): Unit =
    refusedWith(input, Nil, input.toString +: words: _*)

  private def refusedWith(input: Path, args: Seq[String], words: String*): Unit = {
    val out = Scratch.dir("sim-out-").resolve("loads.csv")
    val e = intercept[InputError](
      Main.run(Seq("simulate", "--input", input.toString, "--output", out.toString) ++ args)
    )
    assert(!e.getMessage.contains("\n"), s"error spans lines: ${e.getMessage}")
    words.foreach(w => assert(e.getMessage.contains(w), s"'${e.getMessage}' does not mention '$w'"))
    assert(!Files.exists(out), "an output file was written for a bad input")
  }

  it should "refuse malformed trajectory files with one line naming file, row and column" in {
    refused(text(""), "empty")
    refused(text("# only a comment\n"), "empty")
    refused(text(header + "\n"), "no data rows")
    refused(text(s"$header\n$good\n0.1,0.2\n"), ":3:", "2 values")
    refused(text(s"t1,t2,t3,v1,d2,d3,dd1,dd2,dd3\n$good\n"), "missing column", "'d1'")
    refused(text(s"$good\n$good\n"), "header")
    refused(text(s"$header\n$good\n0.1,0.2,0.3,abc,0,0,0,0,0\n"), ":3:", "'d1'", "not a number")
    refused(text(s"$header\n0.1,0.2,0.3,1,-1,0.5,2,NaN,-4\n"), ":2:", "'dd2'", "not a finite number")
    refused(text(s"$header\n0.1,0.2,0.3,1,-1,0.5,2,3,-Infinity\n"), "'dd3'", "not a finite number")
    refused(text(s"$header\n1e400,0.2,0.3,1,-1,0.5,2,3,4\n"), "'t1'", "not a number")
    refused(text(s"$header\n0.1,0.2,0.3,1e30,-1,0.5,2,3,4\n"), "'d1'", "beyond the declared range")
    refused(text(s"$header\n0.1,0.2,0.3,1,-1,0.5,2,3,-11\n"), "'dd3'", "beyond the declared range")
    refused(text(s"$header,t1\n$good,1\n"), "appears twice")
    refused(file(Array[Byte](0x7f, 'E', 'L', 'F', 0, 0, 1, 2, -1, -2)), "not a text file")
    refused(Scratch.dir("not-a-file"), "is a directory")
    refused(java.nio.file.Paths.get("no/such/t.csv"), "no such file (looked for /")
  }

  it should "refuse a bad --engine or --jobs, a missing output directory, and bad arm rows, with one line and no output" in {
    val ok = text(s"$header\n$good\n")
    refusedWith(ok, Seq("--engine", "fast"), "--engine must be rtl or model", "'fast'")
    refusedWith(ok, Seq("--jobs", "0"), "--jobs must be an integer from 1 to 256", "'0'")
    refusedWith(ok, Seq("--jobs", "two"), "--jobs", "'two'")
    refusedWith(ok, Seq("--robot", "planar3"), "missing column(s) 'q1'")
    val arm = text("q1,q2,q3,qd1,qd2,qd3,qdd1,qdd2,qdd3\n0,0,0,0,3.5,0,0,0,0\n")
    refusedWith(
      arm,
      Seq("--robot", "planar3", "--engine", "model"),
      arm.toString + ":2:",
      "'qd2'",
      "beyond the declared range"
    )
    val e = intercept[InputError](
      Main.run(Seq("simulate", "--input", ok.toString, "--output", "/nonexistent-dir/x/loads.csv"))
    )
    assert(e.getMessage.contains("does not exist") && !e.getMessage.contains("\n"), e.getMessage)
  }

  it should "read and check the trajectory before it compiles the design" in {
    // planar3 at one clock per sample in one multiplier block: a design the compiler refuses.
    val design = Seq("--robot", "planar3", "--max-multipliers", "1", "--clocks-per-sample", "1")
    refusedWith(text(s"$header\n$good\n"), design, "missing column(s) 'q1'")
    val arm = text("q1,q2,q3,qd1,qd2,qd3,qdd1,qdd2,qdd3\n" + Seq.fill(9)("0").mkString(",") + "\n")
    refusedWith(arm, design, "schedule.max-multipliers = 1")
  }

  it should "know a design's trajectory columns from its settings alone, as the compiled design has them" in {
    val arm = Seq("q1", "q2", "q3", "qd1", "qd2", "qd3", "qdd1", "qdd2", "qdd3")
    Seq(
      Seq("--model", "paper") -> header.split(",").toSeq,
      Seq("--robot", "planar3") -> arm,
      (Seq("--robot", "golden/robots/ur5_robot.urdf", "--tip", "tool0", "--max-acceleration", "15") ++
        Seq("--payload.enabled", "true", "--payload.max-mass", "5") ++ PayloadDesigns.scheduleArgs) ->
        ((1 to 6).map(j => s"q$j") ++ (1 to 6).map(j => s"qd$j") ++ (1 to 6).map(j => s"qdd$j") ++
          PayloadColumns.names)
    ).foreach { case (args, expected) =>
      val cli = Cli.parse("simulate", args, Simulate.options, Simulate.flags)
      val early = ReplayColumns.of(cli.params)
      assert(early.columns == expected, args)
      assert(early.payloadColumns == expected.filter(_.startsWith("payload_")), args)
      assert(Simulate.design(cli.compiled).layout == early, args)
    }
  }

  it should "refuse a trajectory with joint columns the robot does not have (q4 for planar3's 3 joints)" in {
    val arm =
      text("q1,q2,q3,qd1,qd2,qd3,qdd1,qdd2,qdd3,q4,qd4,qdd4\n" + Seq.fill(12)("0").mkString(",") + "\n")
    refusedWith(arm, Seq("--robot", "planar3", "--engine", "model"), arm.toString + ":1:", "'q4'", "3 joints")
  }

  it should "write its output with the umask's mode and refuse to replace a read-only one, writing nothing" in {
    import java.nio.file.attribute.PosixFilePermissions
    val dir = Scratch.dir("sim-modes-")
    val plain = Files.createFile(dir.resolve("plain"))
    val expected = Files.getPosixFilePermissions(plain)
    val input = text(s"$header\n$good\n")
    val out = dir.resolve("loads.csv")
    Main.run(Seq("simulate", "--input", input.toString, "--output", out.toString, "--engine", "model"))
    assert(Files.getPosixFilePermissions(out) == expected, "simulate's output mode is not the umask's")
    val first = Files.readAllBytes(out)
    Files.setPosixFilePermissions(out, PosixFilePermissions.fromString("r--r--r--"))
    val e = intercept[InputError](
      Main.run(Seq("simulate", "--input", input.toString, "--output", out.toString, "--engine", "model"))
    )
    assert(e.getMessage.contains("read-only") && e.getMessage.contains(out.toString), e.getMessage)
    assert(java.util.Arrays.equals(Files.readAllBytes(out), first))
    // emit writes with the same mode.
    val emitted =
      Emit.write(Emission("Top", "module Top; endmodule\n", "# r\n", "{}", "x = 1\n"), dir.resolve("gen"))
    assert(emitted.forall(f => Files.getPosixFilePermissions(f) == expected))
  }

  it should "survive seeded random corruptions of a valid file with a one-line error" in {
    val rng = new Random(Seeds("csv-fuzz", 41L))
    val valid = (header +: Seq.fill(5)(good)).mkString("\n")
    val cases = 200
    (0 until cases).foreach { _ =>
      val chars = valid.toCharArray
      val junk = "x,.-e9\n\u0000;\u00ff"
      (0 until 1 + rng.nextInt(4)).foreach(_ =>
        chars(rng.nextInt(chars.length)) = junk(rng.nextInt(junk.length))
      )
      val f = text(new String(chars))
      val out = Scratch.dir("sim-fuzz-").resolve("o.csv")
      // Every check runs before the simulation; a corruption that leaves a valid file is accepted.
      Try(
        {
          val cli = Cli.parse(
            "simulate",
            Seq("--input", f.toString, "--output", out.toString),
            Simulate.options,
            Simulate.flags
          )
          Simulate.prepare(cli, cli.compiled)
        }
      ).failed.foreach {
        case e: InputError => assert(!e.getMessage.contains("\n"), e.getMessage); assert(!Files.exists(out))
        case other         => fail(s"corrupted input gave ${other.getClass.getName}: ${other.getMessage}")
      }
    }
    println(s"[fuzz] simulate: $cases corrupted trajectory files, each accepted or refused with one line")
  }

  it should "stream a hand-written trajectory through the RTL and write idx,load_hw,load_ref,error" in {
    assume(Try(Seq("verilator", "--version").!!).isSuccess, "verilator is not installed")
    val in =
      text(s"$header\n$good\n1.5,-0.7,2.9,2.5,0.5,-1,-9,9,1\n0,0,0,0,0,0,0,0,0\n4,5,6,3,-3,3,-10,10,-10\n")
    val out = Scratch.dir("sim-ok-").resolve("loads.csv")
    Main.run(Seq("simulate", "--input", in.toString, "--output", out.toString, "--model", "paper"))
    val lines = new String(Files.readAllBytes(out), StandardCharsets.UTF_8).trim.split("\n").toSeq
    assert(lines.head == "idx,load_hw,load_ref,error,out_of_range")
    assert(lines.size == 5)
    lines.tail.foreach { l =>
      val cells = l.split(",")
      assert(math.abs(cells(1).toDouble - cells(2).toDouble - cells(3).toDouble) < 1e-9)
      assert(math.abs(cells(3).toDouble) < 1e-3)
    }
  }

  it should "write a seeded trajectory within the declared ranges (run trajectory) that simulate reads without --saturate" in {
    val seed = Seeds("trajectory-command", 81L)
    def write(args: String*): Path = {
      val out = Scratch.dir("trajectory-").resolve("t.csv")
      Main.run(
        Seq("trajectory", "--output", out.toString, "--samples", "500", "--seed", seed.toString) ++ args
      )
      out
    }
    val joint3 = write()
    val table = reducerload.trace.TraceCsv.read(joint3, reducerload.load.Joint3Columns.names)
    assert(table.header.mkString(",") == header && table.rows.size == 500)
    val d = Simulate.design(
      reducerload.compiler.Compiler.compile(reducerload.config.LoadParams.default, "preset default")
    )
    d.limits.foreach { case (c, limit) =>
      val column = table.rows.map(_._2(c))
      assert(column.forall(v => math.abs(v) <= limit), s"column ${d.columns(c)} beyond $limit")
      assert(column.exists(v => math.abs(v) > limit / 2), s"column ${d.columns(c)} does not cover its range")
    }
    assert(table.column("t1").forall(v => math.abs(v) <= math.Pi))
    assert(
      Files.readAllBytes(joint3).sameElements(Files.readAllBytes(write())),
      "the same seed wrote another file"
    )
    val out = Scratch.dir("trajectory-sim-").resolve("loads.csv")
    Main.run(Seq("simulate", "--input", joint3.toString, "--output", out.toString, "--engine", "model"))
    assert(new String(Files.readAllBytes(out), StandardCharsets.UTF_8).linesIterator.size == 501)
    val arm =
      reducerload.trace.TraceCsv.read(write("--robot", "planar3"), reducerload.arm.ArmTrajectory.columns(3))
    assert(arm.rows.size == 500)
    val e = intercept[InputError](Main.run(Seq("trajectory", "--output", joint3.toString, "--samples", "0")))
    assert(e.getMessage.contains("--samples"))
  }
}
