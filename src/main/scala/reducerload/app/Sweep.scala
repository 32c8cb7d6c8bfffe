package reducerload.app

import circt.stage.ChiselStage
import reducerload.cordic.{CordicArchitecture, CordicParams}
import reducerload.arm.LoadReference
import reducerload.compiler.{Compiled, Compiler}
import reducerload.config.{DatapathParams, LoadParams}
import reducerload.load._
import reducerload.trace.TraceCsv
import reducerload.util.{InputError, OutputFile}

import java.nio.file.{Files, Path, Paths}
import scala.jdk.CollectionConverters._
import scala.sys.process._

/**
 * `run sweep`: a design-space benchmark. Elaborates a grid of configurations and measures, for each, the max
 * load error over the golden traces (bit-accurate model; the RTL equals it bit for bit, as the tests check),
 * the derived bound, latency, and the open-tool resource estimate (and the ECP5 Fmax proxy with --fmax).
 * Writes sweep.csv, sweep.md and, with Python + matplotlib, PNG plots. The estimates run like the arm sweep's
 * ([[SweepJobs]]: on Dask by default, cached in target/sweep/joint3/).
 */
object Sweep {
  val options: Seq[Opt] = Seq(
    Opt("out", "DIR", "where the CSV, markdown and plots go", "sweep"),
    Opt(
      "evaluate",
      "ENGINE",
      "where the estimates run: 'dask' (tools/sweep/evaluate.py: cached, resumable, failures recorded; " +
        "docs/distributed-sweeps.md) or 'serial' (in this process, one after another, uncached)",
      "dask"
    ),
    Opt(
      "jobs",
      "N",
      "workers of the local Dask cluster (1..16; each estimate uses one core)",
      "the number of cores"
    ),
    Opt(
      "cluster",
      "ADDRESS",
      "a running Dask scheduler to evaluate on, e.g. tcp://HOST:8786",
      "a local cluster"
    ),
    Opt(
      "cache",
      "DIR",
      "where the emitted points, manifest, results and cached estimates go",
      SweepJobs.defaultStore.toString
    ),
    Opt("robots", "LIST", "with --arms: only these robots (comma-separated)", "all"),
    Opt("schedules", "LIST", "with --arms: only these schedule points (comma-separated)", "all"),
    Opt("seeds", "N", "with --arms and --fmax: placer seeds 1..N per point (not with --evaluate serial)", "1")
  )
  val flags: Seq[String] = Seq("fmax", "arms", "emit-only")
  val flagHelp: Map[String, String] = Map(
    "fmax" -> "place and route every point on ECP5 for the Fmax proxy (1 to 5 minutes each)",
    "emit-only" -> "write each point's Verilog and manifest.json (in --cache) for tools/sweep/evaluate.py, no estimate",
    "arms" -> "sweep every joint of planar3, the UR5 and the Panda over the schedule (clocks per sample, multiplier budget) instead of the joint-3 grid"
  )

  /** The grid: named points, each a complete configuration. */
  def grid: Seq[(String, LoadParams)] = {
    def point(arch: CordicArchitecture, bits: Int, iterations: Int, frac: Int, table: Int = 0) = LoadParams(
      cordic = CordicParams(
        angleBits = bits,
        outputBits = bits,
        iterations = iterations,
        guardBits = if (bits >= 24) 5 else 3,
        angleGuardBits = if (bits >= 24) 5 else 4,
        architecture = arch,
        tableBits = table
      ),
      datapath = DatapathParams(
        velocityFracBits = frac,
        accelerationFracBits = frac,
        constantFracBits = frac + 4,
        internalFracBits = frac,
        outputFracBits = frac
      )
    )
    val classic = Seq((16, 10, 12), (20, 16, 15), (23, 20, 17), (26, 26, 20)).map { case (b, n, f) =>
      s"classic-b$b-n$n" -> point(CordicArchitecture.Classic, b, n, f)
    }
    val residual = Seq((16, 6, 12), (20, 9, 15), (23, 12, 17), (26, 14, 20)).map { case (b, n, f) =>
      s"residual-b$b-n$n" -> point(CordicArchitecture.ResidualRotation, b, n, f)
    }
    val tabled = Seq((16, 6, 12, 4), (20, 9, 15, 7), (23, 12, 17, 8), (26, 14, 20, 9)).map {
      case (b, n, f, t) =>
        s"table-b$b-n$n-t$t" -> point(CordicArchitecture.ResidualRotation, b, n, f, t)
    }
    // Pipeline depth: registers after every r micro-rotations instead of every one.
    val depth = Seq(2, 3).map { r =>
      val p = point(CordicArchitecture.Classic, 26, 26, 20)
      s"classic-b26-n26-r$r" -> p.copy(cordic = p.cordic.copy(iterationsPerStage = r))
    }
    classic ++ depth ++ residual ++ tabled ++ LoadParams.presets.toSeq.map { case (n, p) =>
      s"preset-$n" -> p
    }
  }

  final case class Row(name: String, c: Compiled, maxError: Double, estimate: Estimate) {
    private def p = c.config
    def latency: Int = c.arm.latency
    private def clocksPerSample = c.arm.schedule.clocksPerSample
    def cells: Seq[String] = {
      val fmax = estimate.fmaxEcp5Mhz
      val arch =
        p.cordic.architecture.name + (if (p.cordic.tableBits > 0) s"+table${p.cordic.tableBits}" else "") +
          (if (c.arm.schedule.cordicUnits < c.arm.graph.angles.size) "+shared" else "")
      Seq(
        name,
        p.model.name,
        arch,
        p.cordic.outputBits.toString,
        p.cordic.iterations.toString,
        p.cordic.iterationsPerStage.toString,
        f"$maxError%.3e",
        f"${c.arm.errorBound}%.3e",
        latency.toString,
        fmax.map(f => f"${latency * 1000 / f}%.1f").getOrElse(""),
        fmax.map(f => f"${f * 1e6 / clocksPerSample}%.3g").getOrElse(""),
        estimate.les.toString,
        estimate.registers.toString,
        estimate.mult18x18.toString,
        estimate.memoryBits.toString,
        fmax.map(f => f"$f%.1f").getOrElse("")
      )
    }
  }
  val header: Seq[String] = Seq(
    "config",
    "model",
    "cordic",
    "sincos_bits",
    "iterations",
    "iterations_per_stage",
    "max_error_nm",
    "bound_nm",
    "latency_cycles",
    "latency_ns",
    "results_per_s",
    "est_les",
    "registers",
    "mult18x18",
    "memory_bits",
    "fmax_ecp5_mhz"
  )

  /** Max |model - reference| over every golden trace (reference: the configuration's own formula). */
  def goldenError(c: Compiled): Double = {
    val p = c.config
    val files =
      Files.list(Paths.get("golden")).iterator().asScala.filter(_.toString.endsWith(".csv")).toSeq.sorted
    if (files.isEmpty) throw new InputError("golden/: no traces (run from the repository root)")
    val m = new reducerload.arm.ArmModel(c.arm)
    files.map { f =>
      val t = TraceCsv.read(f, Joint3Columns.names)
      val cols = Joint3Columns.names.map(t.column)
      t.rows.indices.map { i =>
        val s = reducerload.arm.ArmSample.fromRow(cols.map(_(i)))
        math.abs(m.evaluate(s).head - LoadReference.torque(p.robot, p.model, s))
      }.max
    }.max
  }

  /** The command that regenerates a sweep's files, as its markdown names it. */
  def command(arms: Boolean, out: Option[String], fmax: Boolean): String =
    "./sbt \"run sweep" + (if (arms) " --arms" else "") + out.map(d => s" --out $d").getOrElse("") +
      (if (fmax) " --fmax" else "") + "\""

  /** A sweep's CSV text from its cells, header row first (no cell holds a comma). */
  def csv(cells: Seq[Seq[String]]): String = cells.map(_.mkString(",")).mkString("", "\n", "\n")

  /** The cells of a CSV text that [[csv]] wrote. */
  def cellsOf(csvText: String): Seq[Seq[String]] = csvText.linesIterator.map(_.split(",", -1).toSeq).toSeq

  /** A markdown table of a sweep's cells, header row first. */
  def table(cells: Seq[Seq[String]]): Seq[String] = {
    def row(r: Seq[String]) = r.mkString("| ", " | ", " |")
    row(cells.head) +: row(cells.head.map(_ => "---")) +: cells.tail.map(row)
  }

  /**
   * sweep.md from the cells of sweep.csv: a function of the CSV alone, so the docs' freshness test can
   * regenerate the committed markdown from the committed CSV.
   */
  def markdown(cells: Seq[Seq[String]], fmax: Boolean, out: Option[String]): String =
    (Seq(
      "Design-space sweep: " + (if (fmax) "with" else "without") + " the ECP5 Fmax proxy. Regenerate: `" +
        command(arms = false, out, fmax) + "`.",
      "Errors: max |load - formula| over the golden traces (bit-accurate model, equal to the RTL); bound: derived worst case.",
      "Resources: open-tool Cyclone IV E estimate (tools/estimate/README.md). Paper: 4,330 LEs, 321 registers, 10 stages, < 1e-3 N·m.",
      ""
    ) ++ table(cells)).mkString("", "\n", "\n")

  /** The evaluation the command line asks for; every option is checked before anything is elaborated. */
  private def evaluation(cli: Cli): Evaluation = {
    val jobs = cli.get("jobs").map { v =>
      scala.util
        .Try(v.toInt)
        .filter(j => j >= 1 && j <= 16)
        .getOrElse(throw new InputError(s"command line: --jobs must be an integer in 1..16, got '$v'"))
    }
    val evaluation = (cli.get("evaluate"), cli.has("emit-only")) match {
      case (Some(_), true) =>
        throw new InputError("command line: --emit-only and --evaluate exclude each other")
      case (None, true)        => Evaluation.EmitOnly
      case (Some("serial"), _) => Evaluation.Serial
      case (Some("dask") | None, _) =>
        Evaluation.Dask(
          cli
            .get("cluster")
            .fold[Evaluation.Cluster](
              Evaluation.Cluster.Local(jobs.getOrElse(Runtime.getRuntime.availableProcessors.min(16)))
            )(Evaluation.Cluster.At)
        )
      case (Some(e), _) =>
        throw new InputError(s"command line: --evaluate: unknown engine '$e' (known: dask, serial)")
    }
    if (cli.has("cluster") && !evaluation.isInstanceOf[Evaluation.Dask])
      throw new InputError("command line: --cluster needs --evaluate dask")
    evaluation match {
      case Evaluation.Dask(_: Evaluation.Cluster.Local) => evaluation
      case _ if jobs.nonEmpty =>
        throw new InputError(
          "command line: --jobs sets the workers of the local Dask cluster: not with --cluster, --evaluate serial or --emit-only"
        )
      case _ => evaluation
    }
  }

  private def runArms(cli: Cli, out: Path, store: Path, fmax: Boolean, evaluation: Evaluation): Unit = {
    val seeds = cli.get("seeds").fold(1) { v =>
      scala.util
        .Try(v.toInt)
        .filter(n => n >= 1 && n <= 100)
        .getOrElse(throw new InputError(s"command line: --seeds must be an integer in 1..100, got '$v'"))
    }
    if (seeds > 1 && (!fmax || evaluation == Evaluation.Serial))
      throw new InputError(
        "command line: --seeds needs --fmax, and Dask or --emit-only (not --evaluate serial)"
      )
    val selection = ArmSweep.Selection.of(cli.get("robots"), cli.get("schedules"))
    ArmSweep.run(
      out,
      store,
      fmax,
      evaluation,
      command(arms = true, cli.path("out").map(_.toString), fmax),
      selection,
      1 to seeds
    )
  }

  def run(cli: Cli): Unit = {
    val out = cli.pathOr("out", "sweep")
    val fmax = cli.has("fmax")
    // The project's build directory, not the user's: sbt runs in the repository, as tools/ is found there too.
    val store = cli.path("cache").getOrElse(SweepJobs.defaultStore)
    if (!cli.has("arms"))
      Seq("robots", "schedules", "seeds").find(cli.has).foreach { o =>
        throw new InputError(s"command line: --$o needs --arms")
      }
    val how = evaluation(cli)
    if (cli.has("arms")) return runArms(cli, out, store, fmax, how)
    // A preset equal to a grid point is measured once (place and route takes minutes); it is named by its
    // first name in the grid.
    val distinct = grid.map(_._2).distinct
    val names = distinct.map(p => p -> grid.filter(_._2 == p).map(_._1)).toMap
    val compiled = distinct.map(p => p -> Compiler.compile(p, "sweep grid")).toMap
    val points = distinct.zipWithIndex.map { case (p, i) =>
      val c = compiled(p)
      println(s"sweep: elaborating ${i + 1} of ${distinct.size}: ${names(p).mkString(" = ")}")
      SweepJobs.Point(
        names(p).head,
        c.arm.moduleName,
        Emit.withBlackBoxes(
          ChiselStage
            .emitSystemVerilog(new reducerload.arm.ArmDatapath(c.arm), Array.empty[String], Emit.firtoolOpts)
        ),
        Map("configs" -> names(p))
      )
    }
    val errors = distinct.map(p => p -> goldenError(compiled(p))).toMap
    SweepJobs.evaluate(how, store.resolve("joint3"), points, fmax, Seq(1)).foreach { results =>
      val estimates = results.map(r => r.key -> r.estimate).toMap
      // A failed point has no row; the summary names it.
      val rows = grid.flatMap { case (name, p) =>
        estimates(names(p).head).toOption.map(e => Row(name, compiled(p), errors(p), e))
      }
      rows.foreach(r => println(r.cells.mkString("sweep: ", ", ", "")))
      val cells = header +: rows.map(_.cells)
      val md = markdown(cells, fmax, cli.path("out").map(_.toString))
      OutputFile.writeAll(out, Seq("sweep.csv" -> csv(cells), "sweep.md" -> md))
      println(md)
      val plot = Seq("python3", "tools/sweep/plot.py", out.resolve("sweep.csv").toString, out.toString)
      val status = plot.!
      if (status != 0) println(s"sweep: plots not made (${plot.mkString(" ")} exited $status)")
      SweepJobs.finish(results, out.resolve("sweep.csv"))
    }
  }
}
