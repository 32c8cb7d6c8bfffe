package reducerload.app

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.arm.{ArmModel, ArmSample, ArmTrajectory, PayloadColumns}
import reducerload.monitor.{MonitorConfig, MonitorSummary}
import reducerload.sim.replay.ArmReplay
import reducerload.sim.rtl.VerilatorHarness
import reducerload.testutil.Scratch
import reducerload.trace.TraceCsv
import reducerload.util.InputError

import java.io.ByteArrayOutputStream
import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path, Paths}

/**
 * `run simulate` with a run-time payload: the UR5 with `payload.enabled` (at PayloadedArmSpec's 88-clock
 * block-RAM schedule, cheap to compile) replays Pinocchio's pick-and-place trace, whose payload changes five
 * times mid-file, on the model engine; `--payload` for a whole file equals the same payload as columns;
 * payload input a design cannot take is refused in one line.
 */
class SimulatePayloadSpec extends AnyFlatSpec {
  behavior of "simulate with a payload"

  private val golden = Paths.get("golden/arms/payload/ur5_pick_and_place.csv")
  private val ur5 =
    Seq("--robot", "golden/robots/ur5_robot.urdf", "--tip", "tool0", "--max-acceleration", "15")
  private val schedule = reducerload.testutil.PayloadDesigns.scheduleArgs
  private val payload = Seq("--payload.enabled", "true", "--payload.max-mass", "5") ++ schedule
  private val n = 6
  private lazy val compiled =
    Cli.parse("simulate", ur5 ++ payload, Simulate.options, Simulate.flags).compiled
  private lazy val trace = TraceCsv.read(golden, ArmTrajectory.columns(n))

  /** Run simulate on the model engine; returns the output file and what went to standard error. */
  private def simulate(input: Path, args: Seq[String]): (Path, String) = {
    val out = Scratch.dir("sim-payload-").resolve("loads.csv")
    val err = new ByteArrayOutputStream
    Console.withErr(err) {
      Main.run(
        Seq("simulate", "--input", input.toString, "--output", out.toString, "--engine", "model") ++ args
      )
    }
    (out, err.toString(StandardCharsets.UTF_8))
  }

  private def refused(input: Path, args: Seq[String], words: String*): Unit = {
    val e = intercept[InputError](simulate(input, args))
    assert(!e.getMessage.contains("\n"), s"error spans lines: ${e.getMessage}")
    words.foreach(w => assert(e.getMessage.contains(w), s"'${e.getMessage}' does not mention '$w'"))
  }

  /** A CSV of `columns` with the golden trace's rows `rows` (a column not in the trace: `fill`). */
  private def csv(columns: Seq[String], rows: Range, fill: Map[String, String] = Map.empty): Path = {
    val f = Scratch.file("payload-traj-", ".csv")
    val at = columns.map(trace.header.indexOf)
    val lines = rows.map(r =>
      columns
        .zip(at)
        .map { case (c, i) => fill.getOrElse(c, trace.values(r * trace.width + i).toString) }
        .mkString(",")
    )
    Files.writeString(f, (columns.mkString(",") +: lines).mkString("", "\n", "\n"))
    f
  }

  it should "replay the UR5 pick-and-place trace (payload changing mid-file) within the bound and 1e-3 N·m of Pinocchio" in {
    val (out, err) = simulate(golden, ur5 ++ payload)
    assert(!err.contains("no payload given"), err)
    val taus = (1 to n).map(j => s"tau$j")
    val result = TraceCsv.read(out, taus.flatMap(t => Seq(s"${t}_hw", s"${t}_error")) :+ "out_of_range")
    assert(result.size == trace.size)
    assert(result.column("out_of_range").forall(_ == 0), "a row of the declared payload set was flagged")
    val masses = trace.column("payload_mass").distinct
    assert(masses.size >= 4, s"the trace's payloads: $masses")
    val bounds = compiled.arm.errorBounds
    val worst = taus.indices.map { j =>
      val hw = result.column(s"${taus(j)}_hw")
      val pinocchio = trace.column(taus(j))
      val own = result.column(s"${taus(j)}_error").map(math.abs).max
      val vsPinocchio = hw.zip(pinocchio).map { case (a, b) => math.abs(a - b) }.max
      assert(own <= bounds(j), s"joint ${j + 1}: $own beyond the derived bound ${bounds(j)}")
      assert(vsPinocchio <= 1e-3, s"joint ${j + 1}: $vsPinocchio N·m from Pinocchio")
      assert(
        vsPinocchio <= bounds(j) + 1e-9,
        s"joint ${j + 1}: $vsPinocchio N·m from Pinocchio, bound ${bounds(j)}"
      )
      (own, vsPinocchio, bounds(j))
    }
    info(
      s"[payload replay] UR5 pick and place, ${trace.size} rows, ${masses.size} payloads: per joint " +
        worst.map { case (o, v, b) => f"$o%.2e/$v%.2e (bound $b%.2e)" }.mkString(", ") +
        " N·m (vs own reference / vs Pinocchio)"
    )
  }

  it should "code each row's payload as the model does" in {
    val p = compiled.arm
    val replay = new ArmReplay(p)
    val model = new ArmModel(p)
    (0 until trace.size by 7).foreach { r =>
      val row = replay.columns.map(c => trace.values(r * trace.width + trace.header.indexOf(c))).toIndexedSeq
      val body = PayloadColumns.body(row.drop(3 * n))
      assert(replay.encode(row) == model.encode(ArmSample.fromRow(row.take(3 * n)), body), s"row $r")
    }
  }

  it should "give for --payload the same file as the same payload in columns, and say when no payload is given" in {
    val rows = 150 until 200 // carrying part A: one payload
    val values =
      PayloadColumns.names.map(c => trace.values(rows.head * trace.width + trace.header.indexOf(c)))
    assert(values.head > 0)
    val joints = ArmTrajectory.columns(n)
    val (withColumns, _) = simulate(csv(joints ++ PayloadColumns.names, rows), ur5 ++ payload)
    val (withFlag, err) = simulate(csv(joints, rows), ur5 ++ payload :+ "--payload" :+ values.mkString(","))
    assert(!err.contains("no payload given"), err)
    assert(Files.readString(withFlag) == Files.readString(withColumns))
    // Neither: no payload (every parameter 0) and one warning; the same as zero columns.
    val zero = PayloadColumns.names.map(_ -> "0").toMap
    val (withZeros, _) = simulate(csv(joints ++ PayloadColumns.names, rows, zero), ur5 ++ payload)
    val (withNone, warned) = simulate(csv(joints, rows), ur5 ++ payload)
    assert(warned.linesIterator.count(_.contains("no payload given")) == 1, warned)
    assert(Files.readString(withNone) == Files.readString(withZeros))
    assert(Files.readString(withNone) != Files.readString(withColumns))
  }

  it should "refuse payload input the design cannot take, with one line naming the column, row or option" in {
    // A payload file for the UR5 without payload.enabled.
    refused(golden, ur5 ++ schedule, golden.toString, "'payload_mass'", "no run-time payload")
    val joints = ArmTrajectory.columns(n)
    refused(
      csv(joints, 0 until 3),
      ur5 ++ schedule :+ "--payload" :+ "1,0,0,0,0,0,0,0,0,0",
      "--payload needs",
      "payload.enabled"
    )
    // A partial set, a non-number, both sources, a bad --payload.
    val partial = csv(joints ++ PayloadColumns.names.take(4), 0 until 3)
    refused(partial, ur5 ++ payload, partial.toString, "all 10 or none", "'payload_ixx'")
    val bad = csv(joints ++ PayloadColumns.names, 0 until 3, Map("payload_cy" -> "heavy"))
    refused(bad, ur5 ++ payload, bad.toString + ":2:", "'payload_cy'", "not a number")
    val full = csv(joints ++ PayloadColumns.names, 0 until 3)
    refused(full, ur5 ++ payload :+ "--payload" :+ "1,0,0,0,0,0,0,0,0,0", "--payload and the payload columns")
    val plain = csv(joints, 0 until 3)
    refused(plain, ur5 ++ payload :+ "--payload" :+ "1,0,0", "--payload takes 10 numbers", "got 3")
    refused(plain, ur5 ++ payload :+ "--payload" :+ "1,0,0,0,x,0,0,0,0,0", "--payload: payload_ixx: 'x'")
  }

  it should "clamp and flag a payload beyond the declared set (mass above payload.max-mass)" in {
    val joints = ArmTrajectory.columns(n)
    val (out, _) = simulate(csv(joints, 0 until 5), ur5 ++ payload :+ "--payload" :+ "9,0,0,0.05,0,0,0,0,0,0")
    val flags = TraceCsv.read(out, Seq("out_of_range")).column("out_of_range")
    assert(flags.size == 5 && flags.forall(_ == 1), flags)
  }

  it should "give the reducer monitor's summary the loads with each row's payload" in {
    val arm = compiled.arm
    val m = MonitorConfig(arm, compiled.config.monitor)
    val samples = (0 until trace.size).map(r => ArmSample.fromRow(trace.row(r).take(3 * n)))
    val payloads = (0 until trace.size).map(r =>
      PayloadColumns.body(
        PayloadColumns.names.map(c => trace.values(r * trace.width + trace.header.indexOf(c)))
      )
    )
    val summary = MonitorSummary.fromTrajectory(arm, m, samples, Nil, payloads)
    assert(summary.violations.isEmpty, summary.violations.mkString("\n"))
    val unloaded = MonitorSummary.fromTrajectory(arm, m, samples)
    val peaks = (0 until n).map { j =>
      val pinocchio = trace.column(s"tau${j + 1}").map(math.abs).max
      val (hw, ref) = (summary.hardware(j).peakAbsNm.get, summary.reference(j).peakAbsNm.get)
      assert(
        math.abs(ref - pinocchio) <= 1e-9,
        s"joint ${j + 1}: reference peak $ref, Pinocchio's $pinocchio"
      )
      assert(math.abs(hw - pinocchio) <= 1e-3, s"joint ${j + 1}: monitored peak $hw, Pinocchio's $pinocchio")
      (hw, unloaded.hardware(j).peakAbsNm.get)
    }
    assert(peaks.exists { case (loaded, bare) => loaded > bare + 1 }, s"the payload changes no peak: $peaks")
    info(
      s"[payload monitor] peaks with / without the payload: ${peaks.map { case (a, b) => f"$a%.2f/$b%.2f" }.mkString(", ")} N·m"
    )
  }

  it should "write with --monitor.enabled and --summary the monitor's figures from the loads with each row's payload (columns or --payload)" in {
    val rows = 100 until 200 // carrying part A (the heaviest) from rest to rest: one payload
    val joints = ArmTrajectory.columns(n)
    val values =
      PayloadColumns.names.map(c => trace.values(rows.head * trace.width + trace.header.indexOf(c)))
    assert(values.head == 5.0, s"part A: $values")
    def summary(input: Path, args: Seq[String]): String = {
      val json = Scratch.dir("sim-payload-summary-").resolve("summary.json")
      simulate(input, ur5 ++ payload ++ Seq("--monitor.enabled", "true", "--summary", json.toString) ++ args)
      Files.readString(json)
    }
    val withColumns = summary(csv(joints ++ PayloadColumns.names, rows), Nil)
    val withFlag = summary(csv(joints, rows), Seq("--payload", values.mkString(",")))
    val without = summary(csv(joints, rows), Nil)
    assert(withFlag == withColumns, "--payload and the same payload in columns summarise differently")
    assert(without != withColumns, "the summary ignores the payload")
    // Peaks per joint: the hardware's (the models'), then the reference's, against Pinocchio's with the payload.
    val peaks = """"peak_abs_nm": ([-0-9.eE]+)""".r.findAllMatchIn(withColumns).map(_.group(1).toDouble).toSeq
    val bare = """"peak_abs_nm": ([-0-9.eE]+)""".r.findAllMatchIn(without).map(_.group(1).toDouble).toSeq
    (0 until n).foreach { j =>
      val pinocchio =
        rows.map(r => math.abs(trace.values(r * trace.width + trace.header.indexOf(s"tau${j + 1}")))).max
      assert(
        math.abs(peaks(n + j) - pinocchio) <= 1e-9,
        s"joint ${j + 1}: reference peak ${peaks(n + j)}, Pinocchio's $pinocchio"
      )
      assert(
        math.abs(peaks(j) - pinocchio) <= 1e-3,
        s"joint ${j + 1}: monitored peak ${peaks(j)}, Pinocchio's $pinocchio"
      )
    }
    assert(
      (0 until n).exists(j => math.abs(bare(j) - peaks(j)) > 1),
      s"the payload moves no peak: $peaks, $bare"
    )
    info(
      s"[payload monitor] simulate --monitor.enabled --summary, 5 kg: peaks ${peaks.take(n).map(x => f"$x%.2f").mkString(", ")} N·m " +
        s"(without the payload ${bare.take(n).map(x => f"$x%.2f").mkString(", ")})"
    )
  }

  it should "write on the rtl engine the model engine's file, bit for bit, across a payload change" in {
    assume(VerilatorHarness.available, "verilator is not installed")
    // Rows 90..129: at rest with no payload, then part A (5 kg) from row 100 on. The harness build is
    // cached per design (about 45 s on 2 cores the first time).
    val slice = csv(ArmTrajectory.columns(n) ++ PayloadColumns.names, 90 until 130)
    val (model, _) = simulate(slice, ur5 ++ payload)
    val rtl = Scratch.dir("sim-payload-rtl-").resolve("loads.csv")
    Main.run(
      Seq(
        "simulate",
        "--input",
        slice.toString,
        "--output",
        rtl.toString,
        "--engine",
        "rtl"
      ) ++ ur5 ++ payload
    )
    assert(Files.readString(rtl) == Files.readString(model))
  }
}
