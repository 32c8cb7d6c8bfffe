package reducerload.app

import com.typesafe.config.{ConfigFactory, ConfigRenderOptions, ConfigValueFactory}
import reducerload.util.{InputError, OutputFile}

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path, Paths}
import scala.jdk.CollectionConverters._
import scala.sys.process._

/** How a sweep's emitted points are evaluated: the estimate flow, once per point and placer seed. */
sealed trait Evaluation
object Evaluation {

  /**
   * tools/sweep/evaluate.py on Dask (the default): cached, resumable, a failed job recorded and the sweep
   * going on.
   */
  final case class Dask(cluster: Cluster) extends Evaluation

  /** In this process, one estimate after another, uncached: the reference the Dask path is tested against. */
  case object Serial extends Evaluation

  /** Only emit the points and their manifest, for tools/sweep/evaluate.py run elsewhere. */
  case object EmitOnly extends Evaluation

  /** Where the Dask jobs run. */
  sealed trait Cluster
  object Cluster {

    /** `workers` single-threaded processes on this machine, started and stopped by evaluate.py. */
    final case class Local(workers: Int) extends Cluster

    /** A running Dask scheduler, e.g. tcp://HOST:8786 (docs/distributed-sweeps.md: starting one). */
    final case class At(address: String) extends Cluster
  }
}

/** A job's outcome: the estimate, or why it failed and where its log is; `cached`: from an earlier run. */
final case class JobResult(key: String, seed: Int, estimate: Either[String, Estimate], cached: Boolean)

/**
 * Emission and evaluation of a sweep apart (docs/distributed-sweeps.md): the JVM emits every point's Verilog
 * and a manifest naming each file by its SHA-256 (the cache key's design part); the estimates run on Dask
 * through tools/sweep/evaluate.py, or here one after another; the sweep makes its rows from the results.
 */
object SweepJobs {

  /**
   * One emitted design: its key (file name and row), top module and Verilog; `info` goes into the manifest.
   */
  final case class Point(key: String, top: String, verilog: String, info: Map[String, Any]) {
    lazy val sha256: String =
      java.security.MessageDigest
        .getInstance("SHA-256")
        .digest(verilog.getBytes(StandardCharsets.UTF_8))
        .map(b => f"$b%02x")
        .mkString
  }

  /**
   * Where a sweep's points, manifest, results and cache go without `--cache`: the build's directory, never
   * docs.
   */
  val defaultStore: Path = Paths.get("target", "sweep")

  /** The Python driver of the distributed evaluation. */
  val evaluator: Path = Paths.get("tools", "sweep", "evaluate.py")

  /**
   * Every point's Verilog in `dir/points/` and `dir/manifest.json`: per point its key, top, path (relative to
   * the manifest), the file's SHA-256 and its `info`; the placer seeds; whether the Fmax proxy runs.
   */
  def writeManifest(dir: Path, points: Seq[Point], fmax: Boolean, seeds: Seq[Int]): Path = {
    def java(v: Any): Any = v match {
      case m: Map[_, _] => m.map { case (k, x) => k -> java(x) }.asJava
      case s: Seq[_]    => s.map(java).asJava
      case o: Option[_] => o.map(java).orNull
      case x            => x
    }
    val manifest = Map[String, Any](
      "fmax" -> fmax,
      "seeds" -> seeds,
      "points" -> points.map { p =>
        p.info ++ Map("key" -> p.key, "top" -> p.top, "path" -> s"points/${p.key}.sv", "sha256" -> p.sha256)
      }
    )
    OutputFile.writeAll(dir.resolve("points"), points.map(p => s"${p.key}.sv" -> p.verilog))
    val json = ConfigValueFactory
      .fromAnyRef(java(manifest))
      .render(ConfigRenderOptions.concise().setJson(true).setFormatted(true)) + "\n"
    OutputFile.writeAll(dir, Seq("manifest.json" -> json))
    dir.resolve("manifest.json")
  }

  /** The jobs of a results.json that tools/sweep/evaluate.py wrote. */
  def readResults(path: Path): Seq[JobResult] = {
    if (!Files.isRegularFile(path)) throw new InputError(s"$path: no results (the evaluation did not finish)")
    ConfigFactory.parseFile(path.toFile).getConfigList("jobs").asScala.toSeq.map { j =>
      JobResult(
        j.getString("key"),
        j.getInt("seed"),
        if (j.getString("status") == "ok") Right(Estimate.of(j.getConfig("estimate")))
        else Left(s"${j.getString("error")} (log ${j.getString("log")})"),
        j.hasPath("cached") && j.getBoolean("cached")
      )
    }
  }

  /** evaluate.py's exit status when it ran and recorded some jobs as failed (results.json is written). */
  private val someFailed = 1

  /** Run tools/sweep/evaluate.py on the manifest (its cache beside it); its progress goes to the terminal. */
  def dask(manifest: Path, cluster: Evaluation.Cluster): Seq[JobResult] = {
    if (!Files.isRegularFile(evaluator))
      throw new InputError(s"$evaluator not found: run from the repository root")
    val where = cluster match {
      case Evaluation.Cluster.Local(workers) => Seq("--workers", workers.toString)
      case Evaluation.Cluster.At(address)    => Seq("--cluster", address)
    }
    val cmd = Seq("python3", evaluator.toString, manifest.toString) ++ where
    val status = cmd.!
    if (status != 0 && status != someFailed)
      throw new InputError(s"the distributed evaluation failed (${cmd.mkString(" ")} exited $status)")
    readResults(manifest.resolveSibling("results.json"))
  }

  /**
   * The estimates in this process, one after another (seed 1, the estimate's default); a tool's failure is a
   * result.
   */
  def serial(points: Seq[Point], fmax: Boolean): Seq[JobResult] =
    points.zipWithIndex.map { case (p, i) =>
      val estimate =
        try Right(Estimate.run(p.verilog, p.top, fmax))
        catch { case e: InputError => Left(e.getMessage) }
      println(
        s"sweep: estimated ${i + 1} of ${points.size}: ${p.key}: ${estimate.fold(w => s"FAILED: $w", e => s"${e.les} LEs")}"
      )
      JobResult(p.key, 1, estimate, cached = false)
    }

  /**
   * The results of `points` as `evaluation` says, their manifest and Dask's files in `dir`; None when only
   * emitting.
   */
  def evaluate(
      evaluation: Evaluation,
      dir: Path,
      points: Seq[Point],
      fmax: Boolean,
      seeds: Seq[Int]
  ): Option[Seq[JobResult]] = evaluation match {
    case Evaluation.Serial => Some(serial(points, fmax))
    case Evaluation.EmitOnly =>
      val m = writeManifest(dir, points, fmax, seeds)
      println(s"sweep: ${points.size} points emitted; evaluate with: python3 $evaluator $m")
      None
    case Evaluation.Dask(cluster) => Some(dask(writeManifest(dir, points, fmax, seeds), cluster))
  }

  /** How many jobs ran, came from the cache, failed. */
  def summary(results: Seq[JobResult]): String = {
    val failed = results.count(_.estimate.isLeft)
    val cached = results.count(r => r.cached && r.estimate.isRight)
    s"${results.size} jobs: ${results.size - failed - cached} ran, $cached cached, $failed failed"
  }

  /**
   * The sweep's last word, after its files are written: the summary line, and a failed job makes the run fail
   * (exit status 1) so that a script notices; its rows are missing, the others are in `wrote`.
   */
  def finish(results: Seq[JobResult], wrote: Path): Unit = {
    println(s"sweep: ${summary(results)}")
    val failed = results.filter(_.estimate.isLeft)
    if (failed.nonEmpty)
      throw new IllegalStateException(
        s"sweep: ${summary(results)} (${failed.map(r => s"${r.key} seed ${r.seed}").mkString(", ")}); " +
          s"the other rows are in $wrote"
      )
  }
}
