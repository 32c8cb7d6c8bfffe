package reducerload.app

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.testutil.ArmGolden
import reducerload.trace.InputError

import java.nio.file.{Files, Path}

/**
 * `run simulate --summary`: the reducer monitor's figures for a trajectory, checked against counts
 * made here from Pinocchio's golden torques (not from the code under test).
 */
class SimulateSummarySpec extends AnyFlatSpec {
  behavior of "run simulate --summary"

  private val limits = Seq("--monitor.repeated-peak", "[80, 30, 20]", "--monitor.momentary-peak", "[100, 40, 28]", "--monitor.sample-period", "0.01")

  /** Integer field `key` of each joint object, in order. */
  private def fields(json: String, key: String): Seq[Int] =
    s""""$key": (\\d+)""".r.findAllMatchIn(json).map(_.group(1).toInt).toSeq

  it should "count the planar arm's peaks over a golden trajectory as Pinocchio's torques do" in {
    val dir = Files.createTempDirectory("summary")
    val (out, summary) = (dir.resolve("out.csv"), dir.resolve("summary.json"))
    Main.run(Seq("simulate", "--robot", "planar3", "--input", "golden/arms/planar3_multiturn.csv", "--output", out.toString,
      "--summary", summary.toString, "--engine", "model") ++ limits)
    val json = new String(Files.readAllBytes(summary), "UTF-8")
    println(s"[summary] planar3_multiturn: ${json.linesIterator.take(18).mkString(" ").replaceAll("\\s+", " ")} ...")
    val trace = ArmGolden.load("planar3_multiturn.csv")
    val expected = Seq(80.0, 30.0, 20.0).zipWithIndex.map { case (limit, j) => trace.torques.count(t => math.abs(t(j)) > limit) }
    // The hardware's torques are within 2e-4 N·m of Pinocchio's; no golden torque lies that close to a limit.
    Seq(80.0, 30.0, 20.0).zipWithIndex.foreach { case (limit, j) =>
      assert(trace.torques.forall(t => math.abs(math.abs(t(j)) - limit) > 2e-4), s"joint ${j + 1}: a golden torque sits on the limit")
    }
    assert(fields(json, "repeated_peak_samples").take(3) == expected, json)
    assert(fields(json, "samples").take(3) == Seq.fill(3)(trace.samples.size))
    Seq(out, summary).foreach(Files.delete); Files.delete(dir)
  }

  it should "refuse --summary for the joint-3 closed form and an efforts-less planar arm, writing nothing" in {
    val dir = Files.createTempDirectory("summary")
    val summary: Path = dir.resolve("summary.json")
    def refused(args: Seq[String], word: String): Unit = {
      val e = intercept[Exception](Main.run(Seq("simulate", "--output", dir.resolve("out.csv").toString, "--summary", summary.toString,
        "--engine", "model") ++ args))
      assert(e.getMessage.contains(word) && !e.getMessage.contains("\n"), e.getMessage)
      assert(!Files.exists(summary) && !Files.exists(dir.resolve("out.csv")))
    }
    refused(Seq("--input", "golden/random.csv"), "model rnea")
    refused(Seq("--robot", "planar3", "--input", "golden/arms/planar3_random.csv"), "monitor.repeated-peak")
    assert(classOf[InputError].isInstance(intercept[InputError](Main.run(Seq("simulate", "--robot", "planar3", "--input",
      "golden/arms/planar3_random.csv", "--output", dir.resolve("o.csv").toString, "--summary", "/nonexistent/s.json", "--engine", "model")))))
    Files.delete(dir)
  }
}
