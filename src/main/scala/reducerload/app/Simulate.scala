package reducerload.app

import reducerload.arm.{ArmParams, ArmSample, PayloadColumns}
import reducerload.compiler.{Compiled, Compiler}
import reducerload.monitor.{MonitorConfig, MonitorParams, MonitorSummary, RatedReducer}
import reducerload.sim.replay._
import reducerload.sim.rtl.{CompiledHarness, VerilatorHarness}
import reducerload.trace.TraceCsv
import reducerload.util.{InputError, OutputFile}

import java.nio.file.Path
import scala.concurrent.duration.Duration
import scala.concurrent.{Await, ExecutionContext, Future}
import scala.sys.process._
import scala.util.Try

/**
 * `run simulate`: a user's trajectory through the emitted RTL on a compiled Verilator harness (or, with
 * `--engine model`, through the bit-accurate model), in chunks on `--jobs` threads, written as one CSV line
 * per sample with the double-precision reference and the error.
 */
object Simulate {
  val options: Seq[Opt] = Seq(
    Opt(
      "input",
      "FILE",
      "trajectory CSV: header t1,t2,t3,d1,d2,d3,dd1,dd2,dd3 (joint 3), or q1..qN,qd1..qdN,qdd1..qddN (model rnea; with payload.enabled optionally the ten payload columns, see --payload); rad, rad/s, rad/s^2"
    ),
    Opt(
      "output",
      "FILE",
      "result CSV: idx,load_hw,load_ref,error,out_of_range, or idx,tauJ_hw,tauJ_ref,tauJ_error...,out_of_range (N·m; _hw: the output codes as exact decimals)"
    ),
    Opt(
      "engine",
      ReplayEngine.all.map(_.name).mkString("|"),
      "rtl: the emitted Verilog on a compiled Verilator harness; model: the bit-accurate model (same file)",
      ReplayEngine.Rtl.name
    ),
    Opt(
      "jobs",
      "N",
      "chunks of the trajectory run in parallel (harness processes or model threads)",
      "the number of processors"
    ),
    ReplayPayload.option,
    Opt(
      "summary",
      "FILE",
      "model rnea: the reducer monitor's figures per joint (monitor.* settings), from the bit-accurate models, beside the reference's (JSON)"
    )
  )
  val flags: Seq[String] = Seq("saturate")
  val flagHelp: Map[String, String] = Map(
    "saturate" -> "accept values beyond the declared ranges: the hardware clamps them and flags the sample; count them"
  )

  /**
   * The emitted file's header names a regeneration command; a fixed one keeps the harness cache key
   * independent of file names.
   */
  val emitCommand = "./sbt \"run emit\" with the configuration of this simulation"

  private val maxJobs = 256

  private def required(cli: Cli, name: String): Path =
    cli.path(name).getOrElse(throw new InputError(s"command line: simulate needs --$name FILE"))

  private def jobs(cli: Cli): Int = cli.get("jobs") match {
    case None => Runtime.getRuntime.availableProcessors.max(1)
    case Some(v) =>
      Try(v.toInt).toOption
        .filter(n => n >= 1 && n <= maxJobs)
        .getOrElse(
          throw new InputError(s"command line: --jobs must be an integer from 1 to $maxJobs, got '$v'")
        )
  }

  private def engine(cli: Cli): ReplayEngine = {
    val name = cli.get("engine").getOrElse(ReplayEngine.Rtl.name)
    ReplayEngine
      .named(name)
      .getOrElse(
        throw new InputError(
          s"command line: --engine must be ${ReplayEngine.all.map(_.name).mkString(" or ")}, got '$name'"
        )
      )
  }

  /**
   * The compiled design: the joint-3 closed form, or every joint of an arm (model rnea), with its reducer
   * monitor when enabled (the emitted top's host inputs are then held at 0).
   */
  def design(c: Compiled): ReplayDesign[_, _] =
    if (c.config.model.closedForm) new LoadReplay(c.config, c.arm) else new ArmReplay(c.arm, c.monitor)

  /**
   * The checks of a `run simulate` command line that need no compiled design, for a design with `columns`:
   * the options, the output file, the trajectory's header and numbers, where its payload comes from.
   */
  def read(cli: Cli, columns: ReplayColumns): SimulateInput = {
    val input = required(cli, "input")
    val output = required(cli, "output")
    val engineChoice = engine(cli)
    val jobCount = jobs(cli)
    OutputFile.check(output)
    val table = TraceCsv.read(input, columns.required)
    TraceCsv.checkJointColumns(table, columns.required)
    val payload = ReplayPayload.resolve(table, columns.payloadColumns, cli.get(ReplayPayload.option.name))
    if (engineChoice == ReplayEngine.Rtl && !VerilatorHarness.available)
      throw new InputError(
        "simulate needs Verilator on the PATH (Debian: apt-get install verilator), or --engine model"
      )
    SimulateInput(columns, table, payload, output, engineChoice, jobCount, cli.has("saturate"))
  }

  /** Every check of the command line and the input file, before anything runs. */
  def prepare(cli: Cli, compiled: Compiled): SimulateRequest[_, _] =
    prepare(compiled, read(cli, ReplayColumns.of(compiled.config)))

  /** The input's rows in the compiled design's columns, every value checked against its declared range. */
  def prepare(compiled: Compiled, in: SimulateInput): SimulateRequest[_, _] = {
    val d = design(compiled)
    require(
      d.layout == in.columns,
      s"simulate: the input was read for ${in.columns}, the design has ${d.layout}"
    )
    val table = in.table
    // The values as they are when the header is exactly the columns (the usual case): no copy.
    // Otherwise the design's columns picked out (a constant payload filled in), still flat.
    val width = d.columns.size
    val values =
      if (table.header == d.columns) table.values
      else {
        val at = d.columns.map(table.header.indexOf).toArray
        // A column not in the file (at -1) is a constant payload's.
        val constant = new Array[Double](width)
        in.payload match {
          case ReplayPayload.Constant(v) =>
            d.payloadColumns.zip(v).foreach { case (c, x) => constant(d.columns.indexOf(c)) = x }
          case ReplayPayload.Columns | ReplayPayload.Absent =>
        }
        val picked = new Array[Double](table.size * width)
        var r = 0
        while (r < table.size) {
          var c = 0
          while (c < width) {
            picked(r * width + c) = if (at(c) < 0) constant(c) else table.values(r * table.width + at(c))
            c += 1
          }
          r += 1
        }
        picked
      }
    val rows = new SampleRows(width, values)
    if (!in.saturate) {
      val (columns, limits) = (d.limits.map(_._1).toArray, d.limits.map(_._2).toArray)
      def beyond(r: Int, k: Int): Boolean = math.abs(values(r * width + columns(k))) > limits(k)
      var first = -1 // the first value beyond its range, as row * limits + limit
      var count = 0L
      var r = 0
      while (r < rows.size) {
        var k = 0
        while (k < limits.length) {
          if (beyond(r, k)) { if (first < 0) first = r * limits.length + k; count += 1 }
          k += 1
        }
        r += 1
      }
      if (first >= 0) {
        val (i, k) = (first / limits.length, first % limits.length)
        val (c, limit) = (columns(k), limits(k))
        val col = d.columns(c)
        throw new InputError(
          s"${table.source}:${table.lines(i)}: column '$col': ${values(i * width + c)} is beyond the declared range |$col| <= $limit " +
            s"($count value(s) in all; --saturate clamps and counts them, or widen the range)"
        )
      }
    }
    SimulateRequest(compiled, d, rows, in.output, in.engine, in.jobs)
  }

  /**
   * The compiled harness of the design, from exactly the Verilog `emit` writes (cached per design by its
   * hash).
   */
  def harness(request: SimulateRequest[_, _], elaborated: Option[Future[Emission]]): CompiledHarness = {
    val emission = elaborated
      .map(Await.result(_, Duration.Inf))
      .getOrElse(Emit.emit(Emit.bare(request.compiled), Top.Load, emitCommand))
    val start = System.nanoTime()
    val h = VerilatorHarness.compile(emission.verilog, emission.topModule, request.design.ports)
    val seconds = (System.nanoTime() - start) / 1e9
    println(
      if (h.fromCache) s"harness: ${emission.topModule}, cached build ${h.directory}"
      else
        f"harness: ${emission.topModule}, built in $seconds%.0f s (cached for the next run) in ${h.directory}"
    )
    h
  }

  def run(cli: Cli): Unit = {
    // The input is read and checked before the design is compiled (a device fit takes a minute or two for
    // a 6-axis arm): its columns follow from the settings alone.
    val readStart = System.nanoTime()
    val params = cli.params
    val input = read(cli, Compiler.refusedAs(cli.source)(ReplayColumns.of(params)))
    val readSeconds = (System.nanoTime() - readStart) / 1e9
    val summary = cli.path("summary").map { path =>
      if (params.model.closedForm)
        throw new InputError(
          "command line: --summary needs model rnea (the monitor watches every joint of an arm; use --robot)"
        )
      OutputFile.check(path)
      path
    }
    // Elaborate while the values are range-checked; only in memory: the harness is built after every check.
    val compiled = cli.compiled
    val elaborated =
      if (input.engine == ReplayEngine.Rtl)
        Some(Future(Emit.emit(Emit.bare(compiled), Top.Load, emitCommand))(ExecutionContext.global))
      else None
    val checkStart = System.nanoTime()
    val request = prepare(compiled, input)
    println(
      f"input: ${request.rows.size} rows read in $readSeconds%.1f s, checked in ${(System.nanoTime() - checkStart) / 1e9}%.1f s"
    )
    val monitor = summary.map { path =>
      // The monitor's settings resolved against the arm before anything is written: a refusal (a planar arm
      // with no efforts for its limits, say) leaves no output file behind.
      val resolved = Compiler.refusedAs(cli.source)(
        (
          compiled.monitor.getOrElse(MonitorConfig(compiled.arm, compiled.config.monitor)),
          MonitorConfig.rated(compiled.arm, compiled.config.monitor)
        )
      )
      (path, resolved)
    }
    execute(request, elaborated)
    monitor.foreach { case (path, (mp, rated)) => writeSummary(path, request, compiled.arm, mp, rated) }
  }

  /**
   * The monitor's summary of the trajectory: the arm datapath's and the monitor's bit-accurate models (which
   * the RTL tests prove equal to `MonitoredArm` bit for bit) against the double reference, every figure
   * checked against its derived bound.
   */
  private def writeSummary(
      path: Path,
      request: SimulateRequest[_, _],
      arm: ArmParams,
      mp: MonitorParams,
      rated: IndexedSeq[Option[RatedReducer]]
  ): Unit = {
    val n = arm.chain.size
    val samples = (0 until request.rows.size).map { i =>
      val r = request.rows.row(i)
      ArmSample(r.slice(0, n), r.slice(n, 2 * n), r.slice(2 * n, 3 * n))
    }
    // With a run-time payload, each row's (the payload columns after the joints').
    val payloads =
      if (request.design.payloadColumns.isEmpty) Nil
      else
        (0 until request.rows.size).map(i =>
          PayloadColumns.body(request.rows.row(i).slice(3 * n, 3 * n + PayloadColumns.names.size))
        )
    val summary =
      MonitorSummary.fromTrajectory(arm, mp, samples, rated, payloads)
    OutputFile.writeString(path, summary.json)
    println(
      s"wrote $path: reducer monitor summary of ${samples.size} samples, ${n} joints (exponent ${mp.lifeExponents.distinct.mkString("/")})"
    )
    summary.violations.headOption.foreach(v => throw new IllegalStateException(s"monitor summary: $v"))
  }

  /** Run a checked request: write the output file (all of it or nothing) and print the summary. */
  def execute[In, Out](
      request: SimulateRequest[In, Out],
      elaborated: Option[Future[Emission]] = None
  ): ReplaySummary = {
    val d = request.design
    val compiled = request.engine match {
      case ReplayEngine.Rtl   => Some(harness(request, elaborated))
      case ReplayEngine.Model => None
    }
    val progress = ProgressLine.onTerminal(request.rows.size.toLong, s"simulate (${request.engine.name})")
    val summary = OutputFile.write(request.output)(out =>
      Replay.run(d, compiled, request.rows, request.jobs, out, progress)
    )
    println(
      s"wrote ${request.output}: ${summary.samples} samples, ${d.description}, engine ${request.engine.name}, ${request.jobs} job(s)"
    )
    val worst = d.errorLabels.indices.map { j =>
      println(
        f"  max |error| over in-range samples, ${d.errorLabels(j)}%-24s ${summary.maxErrors(j)}%.3e N·m (derived bound ${d.errorBounds(j)}%.3e N·m)"
      )
      (summary.maxErrors(j), d.errorBounds(j))
    }
    println(s"out-of-range samples (clamped, flagged): ${summary.outOfRange}")
    val how = request.engine match {
      case ReplayEngine.Rtl =>
        f"Verilator harness, ${d.throughput}, latency ${d.latency} cycles; " +
          f"${summary.cyclesPerHarnessSecond}%.0f clock cycles/s per harness process (${summary.cyclesPerHarnessCpuSecond}%.0f per CPU second)"
      case ReplayEngine.Model => "bit-accurate model"
    }
    println(
      f"simulation rate: ${summary.samplesPerSecond}%.0f samples/s ($how; JVM side ${summary.samplesPerCpuSecond}%.0f samples per CPU second)"
    )
    summary.phases.foreach { p =>
      def us(seconds: Double) = seconds / summary.samples.max(1) * 1e6
      val engineName = request.engine match {
        case ReplayEngine.Rtl   => "harness process and its files";
        case ReplayEngine.Model => "bit-accurate model"
      }
      println(
        f"replay per sample, wall clock summed over jobs: input codes ${us(p.codes)}%.2f us, engine ${us(p.engine)}%.2f us " +
          f"(${summary.samples / p.engine.max(1e-9)}%.0f samples/s per job: $engineName), result lines ${us(p.lines)}%.2f us (reference and text)"
      )
    }
    worst.zipWithIndex.find { case ((e, b), _) => e > b }.foreach { case ((e, b), j) =>
      throw new IllegalStateException(s"${d.errorLabels(j)}: max error $e exceeds the derived bound $b")
    }
    summary
  }
}
