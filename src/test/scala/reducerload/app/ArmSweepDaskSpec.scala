package reducerload.app

import com.typesafe.config.ConfigFactory
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.testutil.Scratch
import reducerload.util.InputError

import java.nio.file.Files
import scala.jdk.CollectionConverters._
import scala.sys.process._

/**
 * The arm sweep split into emit and a distributed evaluate (tools/sweep/evaluate.py on Dask, the default):
 * the manifest, the options, where the files go, and on a real two-worker cluster on loopback
 * (tools/sweep/test_cluster.py: a worker killed mid-job, a broken point, a second run from the cache, Dask's
 * retries of a job that raises) the same rows as the serial run; a failed point fails the sweep after its
 * files are written.
 */
class ArmSweepDaskSpec extends AnyFlatSpec {
  behavior of "the distributed arm sweep"

  private val small = ArmSweep.Selection(Seq("planar3"), Seq("ii64", "ii256"))
  private lazy val designs = ArmSweep.designs(small)

  private def sweepCli(args: String*) = Cli.parse("sweep", args, Sweep.options, Sweep.flags, design = false)

  it should "refuse options of the distributed sweep out of place, with one line" in {
    def refused(args: Seq[String], word: String): Unit = {
      val e = intercept[InputError](Sweep.run(sweepCli(args: _*)))
      assert(e.getMessage.contains(word) && !e.getMessage.contains("\n"), e.getMessage)
    }
    refused(Seq("--robots", "planar3"), "--robots needs --arms")
    refused(Seq("--seeds", "2", "--fmax"), "--seeds needs --arms")
    refused(
      Seq("--arms", "--evaluate", "serial", "--cluster", "tcp://127.0.0.1:8786"),
      "--cluster needs --evaluate dask"
    )
    refused(Seq("--emit-only", "--cluster", "tcp://127.0.0.1:8786"), "--cluster needs --evaluate dask")
    refused(Seq("--arms", "--evaluate", "ray"), "unknown engine 'ray' (known: dask, serial)")
    refused(Seq("--arms", "--evaluate", "dask", "--emit-only"), "exclude each other")
    refused(Seq("--arms", "--schedules", "ii3"), "--schedules: unknown 'ii3'")
    refused(Seq("--arms", "--robots", "r2d2"), "--robots: unknown 'r2d2'")
    refused(Seq("--arms", "--emit-only", "--seeds", "3"), "--seeds needs --fmax")
    refused(Seq("--arms", "--evaluate", "serial", "--fmax", "--seeds", "3"), "not --evaluate serial")
    refused(
      Seq("--jobs", "2", "--cluster", "tcp://127.0.0.1:8786"),
      "--jobs sets the workers of the local Dask cluster"
    )
    refused(Seq("--arms", "--jobs", "2", "--evaluate", "serial"), "--jobs sets the workers")
    refused(Seq("--jobs", "0"), "--jobs must be an integer in 1..16")
  }

  it should "write every point's Verilog and a manifest naming it by SHA-256" in {
    val dir = Scratch.dir("arms-emit-")
    val manifest =
      ConfigFactory.parseFile(SweepJobs.writeManifest(dir, designs.map(_.job), fmax = false, Seq(1)).toFile)
    val points = manifest.getConfigList("points").asScala.toSeq
    assert(points.map(_.getString("key")) == Seq("planar3-ii64", "planar3-ii256"))
    assert(manifest.getIntList("seeds").asScala.toSeq == Seq(1) && !manifest.getBoolean("fmax"))
    points.zip(designs).foreach { case (m, d) =>
      val bytes = Files.readAllBytes(dir.resolve(m.getString("path")))
      val sha = java.security.MessageDigest.getInstance("SHA-256").digest(bytes).map(b => f"$b%02x").mkString
      assert(m.getString("sha256") == sha && sha == d.job.sha256 && m.getString("top") == d.top)
      assert(m.getInt("settings.clocks_per_sample") == d.p.schedule.clocksPerSample)
      assert(m.getString("robot") == "planar3" && m.getString("point") == d.point)
    }
  }

  it should "merge a row per point and seed, and none for a failed job" in {
    def est(les: Int, mhz: Double) = Estimate(les, 1, 2, 3, 4, 5, 6, Some(mhz), None, None)
    val Seq(a, b) = designs
    val results = Seq(
      JobResult(a.key, 1, Right(est(100, 120.0)), cached = true),
      JobResult(a.key, 2, Right(est(100, 130.0)), cached = false),
      JobResult(b.key, 1, Left("timed out after 3 s (log x.log)"), cached = false),
      JobResult(b.key, 2, Right(est(90, 110.0)), cached = false)
    )
    val rows = ArmSweep.merge(designs, results, Seq(1, 2))
    assert(
      rows.map(r => (r.point, r.fmax)) == Seq(
        ("ii64-s1", Some(120.0)),
        ("ii64-s2", Some(130.0)),
        ("ii256-s2", Some(110.0))
      )
    )
    assert(ArmSweep.merge(designs, results.filter(_.seed == 1), Seq(1)).map(_.point) == Seq("ii64"))
    assert(SweepJobs.summary(results) == "4 jobs: 2 ran, 1 cached, 1 failed")
  }

  it should "put the points, manifest and cache under target/sweep by default, or in --cache, never in --out" in {
    assert(SweepJobs.defaultStore == java.nio.file.Paths.get("target", "sweep"))
    assert(Sweep.options.find(_.name == "cache").map(_.default).contains("target/sweep"))
    // Emitting only: no estimate, so this runs the real command line in a second.
    val dir = Scratch.dir("arms-cache-")
    val (out, cache) = (dir.resolve("out"), dir.resolve("cache"))
    val args = Seq("sweep", "--arms", "--robots", "planar3", "--schedules", "ii256", "--emit-only")
    assert(Main.execute(args ++ Seq("--out", out.toString, "--cache", cache.toString)) == 0)
    assert(Files.isRegularFile(cache.resolve("arms/manifest.json")))
    assert(Files.isRegularFile(cache.resolve("arms/points/planar3-ii256.sv")))
    assert(!Files.exists(out), s"--emit-only wrote into --out $out")
  }

  it should "give the serial run's rows on a two-worker cluster that loses a worker mid-job, recompute nothing the second time, retry a job that raises, and fail a sweep with a failed point after writing the rest" in {
    if (scala.util.Try(Seq("python3", "--version").!!).isFailure) {
      val reason = "python3 not on PATH: the distributed sweep's cluster test is skipped"
      println(s"ArmSweepDaskSpec: $reason")
      info(reason)
    } else {
      val serialResults = SweepJobs.serial(designs.map(_.job), fmax = false)
      assert(SweepJobs.summary(serialResults) == "2 jobs: 2 ran, 0 cached, 0 failed")
      val serial = ArmSweep.merge(designs, serialResults, Seq(1))
      val dir = Scratch.dir("arms-dask-")
      val manifest = SweepJobs.writeManifest(dir, designs.map(_.job), fmax = false, Seq(1))
      val work = dir.resolve("work")
      val cmd =
        Seq("python3", "tools/sweep/test_cluster.py", manifest.toString, work.toString, "--deadline", "1200")
      val log = new StringBuilder
      val status = cmd.!(
        ProcessLogger((l: String) => { println(l); log.append(l).append('\n') }, (l: String) => println(l))
      )
      assert(status == 0, s"${cmd.mkString(" ")} exited $status:\n$log")
      val rows = ArmSweep.merge(designs, SweepJobs.readResults(work.resolve("results.json")), Seq(1))
      assert(rows.map(_.cells) == serial.map(_.cells))
      assert(log.toString.contains("mid-job") && log.toString.contains("recomputes nothing"))
      assert(log.toString.contains("retries times"))
      // The run with the broken point: its files written with the good rows, then a failed run (exit status 1).
      val out = dir.resolve("out")
      val withBroken = SweepJobs.readResults(work.resolve("results1.json"))
      val e = intercept[IllegalStateException](
        ArmSweep.report(out, designs, withBroken, Seq(1), fmax = false, "test")
      )
      assert(e.getMessage.contains("3 jobs: 2 ran, 0 cached, 1 failed (broken seed 1)"), e.getMessage)
      val csv = Sweep.cellsOf(new String(Files.readAllBytes(out.resolve("arms.csv")), "UTF-8"))
      assert(
        csv.tail.map(_(1)) == Seq("ii64", "ii256") && csv.tail.map(_.mkString(",")) == serial.map(
          _.cells.mkString(",")
        )
      )
    }
  }
}
