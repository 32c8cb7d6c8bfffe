package reducerload.app

import reducerload.testutil.Scratch
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.testutil.{ArmGolden, ArmGoldenTrace, PayloadDesigns}
import reducerload.util.InputError

import java.nio.file.{Files, Path}

/**
 * `run simulate --summary`: the reducer monitor's figures for a trajectory (planar3 and the UR5), checked
 * against counts and T_av made here from Pinocchio's golden torques (not from the code under test); the
 * command itself fails when a figure is beyond its derived bound.
 */
class SimulateSummarySpec extends AnyFlatSpec {
  behavior of "run simulate --summary"

  /** Integer field `key` of each joint object, in order. */
  private def fields(json: String, key: String): Seq[Int] =
    s""""$key": (\\d+)""".r.findAllMatchIn(json).map(_.group(1).toInt).toSeq

  /** Number field `key` of each object that has it, in order (joints, reference, difference, bound). */
  private def numbers(json: String, key: String): Seq[Double] =
    s""""$key": ([-0-9.eE]+)""".r.findAllMatchIn(json).map(_.group(1).toDouble).toSeq

  /**
   * `simulate --summary` of a golden trace with per-joint limits (and the robot's arguments); checks the
   * repeated-peak counts against Pinocchio's torques (no golden torque may lie within `margin` of a limit)
   * and returns the summary JSON.
   */
  private def summarize(
      robotArgs: Seq[String],
      file: String,
      repeated: Seq[Double],
      momentary: Seq[Double],
      period: Double,
      margin: Double
  ): (String, ArmGoldenTrace) = {
    val dir = Scratch.dir("summary")
    val (out, summary) = (dir.resolve("out.csv"), dir.resolve("summary.json"))
    def list(xs: Seq[Double]) = xs.mkString("[", ", ", "]")
    Main.run(
      Seq("simulate") ++ robotArgs ++ Seq(
        "--input",
        s"golden/arms/$file",
        "--output",
        out.toString,
        "--summary",
        summary.toString,
        "--engine",
        "model",
        "--monitor.repeated-peak",
        list(repeated),
        "--monitor.momentary-peak",
        list(momentary),
        "--monitor.sample-period",
        period.toString
      )
    )
    val json = new String(Files.readAllBytes(summary), "UTF-8")
    val trace = ArmGolden.load(file)
    val n = repeated.size
    println(
      s"[summary] ${trace.name}: ${json.linesIterator.take(18).mkString(" ").replaceAll("\\s+", " ")} ..."
    )
    repeated.zipWithIndex.foreach { case (limit, j) =>
      assert(
        trace.torques.forall(t => math.abs(math.abs(t(j)) - limit) > margin),
        s"joint ${j + 1}: a golden torque sits on the limit"
      )
    }
    val expected = repeated.zipWithIndex.map { case (limit, j) =>
      trace.torques.count(t => math.abs(t(j)) > limit)
    }
    assert(fields(json, "repeated_peak_samples").take(n) == expected, json)
    assert(fields(json, "samples").take(n) == Seq.fill(n)(trace.samples.size))
    Seq(out, summary).foreach(Files.delete); Files.delete(dir)
    (json, trace)
  }

  it should "count the planar arm's peaks over a golden trajectory as Pinocchio's torques do" in {
    // The hardware's torques are within 2e-4 N·m of Pinocchio's; no golden torque lies that close to a limit.
    summarize(
      Seq("--robot", "planar3"),
      "planar3_multiturn.csv",
      Seq(80.0, 30.0, 20.0),
      Seq(100.0, 40.0, 28.0),
      0.01,
      2e-4
    )
  }

  it should "pass its own bound checks on the UR5, loads from 0.3 N·m, with T_av as Pinocchio's torques give it" in {
    // A schedule of its own: the monitor's figures do not depend on it (the numerics are the graph's), and the
    // device fit's search would take about 100 s.
    val ur5 = Seq("--robot", "golden/robots/ur5_robot.urdf", "--tip", "tool0", "--max-acceleration", "15") ++
      PayloadDesigns.scheduleArgs
    // Limits where ur5_rest_to_rest crosses them (peaks about 8.7, 66, 19, 1.7, 2.6, 0.31 N·m); derived torque bounds <= 3.5e-4 N·m.
    val (json, trace) = summarize(
      ur5,
      "ur5_rest_to_rest.csv",
      Seq(5.0, 40.0, 12.0, 1.0, 1.5, 0.2),
      Seq(8.0, 60.0, 18.0, 1.5, 2.4, 0.3),
      0.005,
      3.5e-4
    )
    // T_av from Pinocchio's torques and the trace's speeds (p = 3), against the summary's hardware figure and its bound.
    val hw = numbers(json, "avg_torque_nm")
    val bound = hw.drop(18)
    (0 until 6).foreach { j =>
      val w = trace.samples.map(s => math.abs(s.qd(j)))
      val pinocchio =
        math.cbrt(trace.torques.zip(w).map { case (t, x) => x * math.pow(math.abs(t(j)), 3) }.sum / w.sum)
      println(
        f"[summary] ur5 joint ${j + 1}: T_av ${hw(j)}%.6f N·m (Pinocchio $pinocchio%.6f, double reference ${hw(6 + j)}%.6f, bound ${bound(j)}%.2e)"
      )
      assert(
        hw(j) > 0 && math.abs(hw(j) - pinocchio) <= bound(j) + 1e-6 * pinocchio,
        s"joint ${j + 1}: T_av ${hw(j)} vs Pinocchio's $pinocchio"
      )
    }
  }

  it should "refuse --summary for the joint-3 closed form and an efforts-less planar arm, writing nothing" in {
    val dir = Scratch.dir("summary")
    val summary: Path = dir.resolve("summary.json")
    def refused(args: Seq[String], word: String): Unit = {
      val e = intercept[Exception](
        Main.run(
          Seq(
            "simulate",
            "--output",
            dir.resolve("out.csv").toString,
            "--summary",
            summary.toString,
            "--engine",
            "model"
          ) ++ args
        )
      )
      assert(e.getMessage.contains(word) && !e.getMessage.contains("\n"), e.getMessage)
      assert(!Files.exists(summary) && !Files.exists(dir.resolve("out.csv")))
    }
    refused(Seq("--input", "golden/random.csv"), "model rnea")
    refused(Seq("--robot", "planar3", "--input", "golden/arms/planar3_random.csv"), "monitor.repeated-peak")
    assert(
      classOf[InputError].isInstance(
        intercept[InputError](
          Main.run(
            Seq(
              "simulate",
              "--robot",
              "planar3",
              "--input",
              "golden/arms/planar3_random.csv",
              "--output",
              dir.resolve("o.csv").toString,
              "--summary",
              "/nonexistent/s.json",
              "--engine",
              "model"
            )
          )
        )
      )
    )
    Files.delete(dir)
  }
}
