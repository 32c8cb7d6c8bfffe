package reducerload.app

import circt.stage.ChiselStage
import reducerload.arm.{ArmDatapath, ArmGolden, ArmModel, ArmParams}
import reducerload.config.LoadParams
import reducerload.graph.{ListOrder, Reassociation, ScheduleRequest, Scheduler, Storage}
import reducerload.util.{InputError, OutputFile}

import java.nio.file.Path
import scala.sys.process._

/**
 * `run sweep --arms`: every joint of planar3, the UR5 and the Panda (the golden traces' robots and ranges)
 * over the schedule axis, from one operator per operation to one multiplier unit per operand width. Per
 * point: clocks per sample, latency, multiplier blocks, the open-tool estimate (and Fmax proxy with --fmax),
 * samples/s, and per joint the measured max error against Pinocchio over the golden traces (bit-accurate
 * model; the RTL equals it bit for bit, as the tests check) beside the derived bound. Writes arms.csv,
 * arms.md and, with Python + matplotlib, arms_pareto.png.
 *
 * Emission (the JVM) and evaluation (the estimate flow, minutes per point) are apart ([[SweepJobs]]): the
 * points go to Dask through tools/sweep/evaluate.py (cached, resumable), or are estimated here one after
 * another; either way the rows are written by [[write]] (docs/distributed-sweeps.md).
 */
object ArmSweep {

  /** The clock the samples/s column assumes without the Fmax proxy: the issue's target clock. */
  val nominalMhz: Double = 150.0

  val robots: Seq[String] = Seq("planar3", "ur5", "panda")

  /**
   * A CORDIC unit of fewer pipeline stages than the robot's: a start table of 2^tableBits entries
   * (`cordic.table-bits`) and `iterationsPerStage` micro-rotations between registers.
   */
  final case class ShortCordic(tableBits: Int, iterationsPerStage: Int)

  /**
   * One point of the schedule axis: its name, the schedule asked for, the per-torque error target (none: the
   * default fraction bits), how sums (and products) are rebuilt (`datapath.reassociate`), whether routes
   * between units pass registers (`datapath.registered-routes`, with every held value in registers:
   * `datapath.memory-delay-min-cycles = 0`, the combination measured to route), a shorter CORDIC unit and
   * whether runs of parallel axes are crossed in one rotation (`datapath.compose-parallel-axes`).
   */
  final case class Point(
      name: String,
      request: ScheduleRequest,
      targetError: Seq[Double] = Nil,
      reassociate: Reassociation = Reassociation.Off,
      routed: Boolean = false,
      cordic: Option[ShortCordic] = None,
      composeParallelAxes: Boolean = false
  ) {

    /** The robot's golden-trace configuration with this point's settings. */
    def config(base: LoadParams): LoadParams =
      base.copy(
        targetError = targetError,
        schedule = request,
        cordic = cordic.fold(base.cordic)(c =>
          base.cordic.copy(tableBits = c.tableBits, iterationsPerStage = c.iterationsPerStage)
        ),
        datapath = base.datapath.copy(
          reassociate = reassociate,
          registeredRoutes = Some(routed),
          memoryDelayMinCycles = if (routed) 0 else base.datapath.memoryDelayMinCycles,
          composeParallelAxes = composeParallelAxes
        )
      )
  }

  /**
   * `schedule.refinement` of the fast point: on the UR5 five times the default takes another ~400 LEs off
   * (15,229 -> 14,832 estimated) for about 10 s more.
   */
  val fastRefinement: Int = 100000

  /**
   * The fast point: the fewest clocks within 66 blocks at 1e-3 N·m with the shortest latency; the sweep has
   * it with and without registered routes.
   */
  private val fast = Point(
    "fast66-t1e-3",
    ScheduleRequest(
      clocksPerSample = None,
      maxMultipliers = Some(66),
      listOrder = Some(ListOrder.ByHeight),
      refinement = ArmSweep.fastRefinement
    ),
    Seq(1e-3),
    Reassociation.Sums
  )

  /** Issue 33's latency point without forwarding (see [[schedules]]). */
  private val parallel = fast.copy(
    name = "parallel66-t1e-3",
    request = fast.request.copy(scheduler = Scheduler.CpSat),
    reassociate = Reassociation.SumsAndProducts,
    routed = true,
    composeParallelAxes = true
  )

  /** Issue 33's latency point with products read from block RAM (`schedule.product-memories`). */
  private val memories = parallel.copy(
    name = "memories66-t1e-3",
    request = parallel.request.copy(productMemories = true)
  )

  /** The products that stay out of the memories in shared registers (`schedule.share-registers`). */
  private val memoriesShared = memories.copy(
    name = "memories-shared66-t1e-3",
    request = memories.request.copy(shareRegisters = true)
  )

  /**
   * The schedule axis: intervals from one clock to hundreds, and the fewest clocks within an EP4CE30's 66
   * blocks; then two of them with the fraction bits fitted to 1e-3 N·m (`numeric.target-error`); then the
   * fewest clocks within 66 blocks at 1e-3 with the shortest latency (sums rebuilt as trees, the list placed
   * by height, the schedule refined five times longer than by default: issue 33's UR5 point), and the same
   * with registered routes (the design that routes on the clock proxy), also on the solver's shortest
   * schedule (`schedule.scheduler = cp-sat`), and on it with products reassociated, the products of slack 0
   * forwarded and a CORDIC unit of two micro-rotations per stage from a 2^11 table (`datapath.reassociate =
   * sums-and-products`, `schedule.forward-slack = 0`: issue 33's first latency point), and on it with
   * products reassociated and runs of parallel axes crossed in one rotation, no product forwarded
   * (`datapath.compose-parallel-axes`: issue 33's latency point without forwarding), and that point with the
   * sums of products that lengthen no path summed on accumulators (`schedule.accumulate-slack = 0`: fewer LEs
   * at the same latency), and that point with the products read a few clocks after they are ready taken from
   * a block RAM per unit (`schedule.product-memories`), alone and with the rest in shared registers
   * (`schedule.share-registers`: fewer LEs again), and with the sines and cosines read a few clocks after
   * they are ready taken from block RAMs too (`schedule.sin-cos-memories`: the smallest); then values in
   * block-RAM banks (`schedule.storage = memory`) at 1e-3 N·m from 32 to 512 clocks (88: the UR5 design that
   * meets issue 12's targets; 114: the Panda's, and at 114 with 5 adder units, which the Panda's latency
   * target needs).
   */
  val schedules: Seq[Point] =
    Seq(1, 4, 16, 64, 256).map(c => Point(s"ii$c", ScheduleRequest(clocksPerSample = Some(c)))) ++ Seq(
      Point("budget66", ScheduleRequest(clocksPerSample = None, maxMultipliers = Some(66))),
      Point("budget66-t1e-3", ScheduleRequest(clocksPerSample = None, maxMultipliers = Some(66)), Seq(1e-3)),
      Point("ii64-t1e-3", ScheduleRequest(clocksPerSample = Some(64)), Seq(1e-3)),
      fast,
      fast.copy(name = "routed66-t1e-3", routed = true),
      fast.copy(
        name = "routed66-cpsat-t1e-3",
        request = fast.request.copy(scheduler = Scheduler.CpSat),
        routed = true
      ),
      fast.copy(
        name = "latency66-t1e-3",
        request = fast.request.copy(scheduler = Scheduler.CpSat, forwardSlack = Some(0)),
        reassociate = Reassociation.SumsAndProducts,
        routed = true,
        cordic = Some(ShortCordic(tableBits = 11, iterationsPerStage = 2))
      ),
      parallel,
      parallel.copy(
        name = "accumulate66-t1e-3",
        request = parallel.request.copy(accumulateSlack = Some(0))
      ),
      memories,
      memoriesShared,
      memoriesShared.copy(
        name = "memories-sincos66-t1e-3",
        request = memoriesShared.request.copy(sinCosMemories = true)
      )
    ) ++
      Seq(32, 64, 88, 114, 128, 512).map(c =>
        Point(
          s"mem-ii$c-t1e-3",
          ScheduleRequest(clocksPerSample = Some(c), storage = Some(Storage.Memory)),
          Seq(1e-3)
        )
      ) :+
      Point(
        "mem-ii114-a5-t1e-3",
        ScheduleRequest(clocksPerSample = Some(114), storage = Some(Storage.Memory), adderUnits = Some(5)),
        Seq(1e-3)
      )

  final case class Row(
      robot: String,
      point: String,
      p: ArmParams,
      errors: IndexedSeq[Double],
      estimate: Estimate
  ) {
    private val s = p.schedule
    def fmax: Option[Double] = estimate.fmaxEcp5Mhz
    def samplesPerSecond: Double = s.samplesPerSecond(fmax.getOrElse(nominalMhz) * 1e6)
    def cells: Seq[String] = Seq(
      robot,
      point,
      p.chain.size.toString,
      p.internalFracBits.toString,
      s.request.stored.name,
      s.clocksPerSample.toString,
      p.latency.toString,
      f"${p.latency * 1000 / fmax.getOrElse(nominalMhz)}%.0f",
      f"$samplesPerSecond%.3g",
      s.multiplierUnits.toString,
      p.banked.fold(p.graph.counts.additions + p.graph.counts.negations)(_.adderUnits).toString,
      s.cordicUnits.toString,
      s.multiplierBlocks.toString,
      estimate.mult18x18.toString,
      estimate.les.toString,
      estimate.registers.toString,
      estimate.memoryBits.toString,
      estimate.m9kBlocks.toString,
      fmax.map(f => f"$f%.1f").getOrElse(""),
      f"${errors.max}%.2e",
      f"${p.errorBound}%.2e",
      errors.map(e => f"$e%.1e").mkString(" "),
      p.errorBounds.map(e => f"$e%.1e").mkString(" ")
    )
  }
  val header: Seq[String] = Seq(
    "robot",
    "schedule",
    "joints",
    "internal_frac_bits",
    "storage",
    "clocks_per_sample",
    "latency_cycles",
    "latency_ns",
    "samples_per_s",
    "mul_units",
    "adder_units",
    "cordic_units",
    "mult_blocks",
    "est_mult18x18",
    "est_les",
    "registers",
    "memory_bits",
    "est_m9k",
    "fmax_ecp5_mhz",
    "max_error_nm",
    "bound_nm",
    "max_error_per_joint",
    "bound_per_joint"
  )

  /** Max |model - Pinocchio| per joint over every golden trace of `robot`. */
  def goldenErrors(p: ArmParams, robot: String): IndexedSeq[Double] = {
    val model = new ArmModel(p)
    val traces = ArmGolden.of(robot)
    p.jointNames.indices.map { j =>
      traces
        .flatMap(t =>
          t.samples.zip(t.torques).map { case (s, tau) => math.abs(model.evaluate(s)(j) - tau(j)) }
        )
        .max
    }
  }

  /**
   * arms.md from the cells of arms.csv and the command that made them: a function of the CSV alone, so the
   * docs' freshness test can regenerate the committed markdown from the committed CSV.
   */
  def markdown(
      cells: Seq[Seq[String]],
      fmax: Boolean,
      command: String,
      cpu: Option[Seq[Seq[String]]] = None
  ): String =
    (Seq(
      s"Arm sweep ${if (fmax) "with" else "without"} the ECP5 Fmax proxy. Regenerate: `$command`.",
      s"Latency in ns and samples/s at ${if (fmax) "the Fmax proxy" else s"$nominalMhz MHz"}. Errors: max |torque - Pinocchio| over the golden " +
        "traces per joint (bit-accurate model, equal to the RTL); bound: derived worst case over the declared ranges.",
      "Resources: open-tool Cyclone IV E estimate (tools/estimate/README.md); mult_blocks: the schedule's 18x18 blocks; est_m9k: the estimate's 9-kbit M9K blocks. EP4CE30: 28,848 LEs, 66 multipliers, 66 M9K blocks.",
      ""
    ) ++ Sweep.table(cells) ++ cpu.toSeq.flatMap(c =>
      Seq(
        "",
        "Beside the CPU (cpu.csv, `tools/bench/pinocchio_rnea.py --codegen --csv docs/sweep/cpu.csv`: plain " +
          "Pinocchio and RNEA generated with the robot's constants folded, one core of the machine named):",
        ""
      ) ++ anchors(cells, c)
    )).mkString("", "\n", "\n")

  /** The point a row of arms.csv was made at: its schedule, less the `-sN` of a run of several seeds. */
  def pointOf(schedule: String): Option[Point] =
    schedules.find(p =>
      schedule == p.name || schedule.matches(java.util.regex.Pattern.quote(p.name) + "-s[0-9]+")
    )

  /**
   * Whether a row's design routes on the clock proxy: registers storage above
   * [[reducerload.graph.Schedule.directMaxClocks]] clocks per sample routes only with registered routes and
   * no product forwarded past them, and not with shared registers (docs/timing-closure.md: the UR5's direct
   * designs at 17-18 clocks did not route at all, nor did its registered-routes designs with
   * `schedule.forward-slack = 0`; with shared registers the router is slow: the UR5's latency recipe with
   * product memories routed on one seed of two, the Panda's did not within an hour); a row of no point of
   * this sweep counts as direct.
   */
  def routes(row: Map[String, String]): Boolean =
    pointOf(row("schedule")).exists(p =>
      p.routed && p.request.forwardSlack.isEmpty && !p.request.shareRegisters
    ) ||
      row("storage") != Storage.Registers.name ||
      row("clocks_per_sample").toInt <= reducerload.graph.Schedule.directMaxClocks

  /**
   * The FPGA beside the CPU, per robot of `cpu` (the rows tools/bench/pinocchio_rnea.py --csv wrote,
   * docs/sweep/cpu.csv): the sweep's points that fit an EP4CE30 (multiplier blocks, estimated LEs and M9K
   * within it) and route on the clock proxy ([[routes]]: a rate at a clock the design does not reach is no
   * anchor), with the most samples/s and with the least latency, then each CPU engine, one sample a call. A
   * function of the two CSVs: arms.md and the README's table are made from it.
   */
  def anchors(arms: Seq[Seq[String]], cpu: Seq[Seq[String]], detail: Boolean = true): Seq[String] = {
    def rows(cells: Seq[Seq[String]]) = cells.tail.map(r => cells.head.zip(r).toMap)
    val device = reducerload.config.Device.EP4CE30
    val fits = rows(arms).filter(r =>
      r("mult_blocks").toInt <= device.multiplierBlocks && r("est_les").toInt <= device.logicElements &&
        r("est_m9k").toInt <= device.memoryBlocks &&
        routes(r)
    )
    val engines = rows(cpu)
    def rate(x: Double) = f"${x / 1e6}%.2f M"
    val header = Seq("robot", "engine", "samples/s", "latency (us)", "what")
    val lines = engines.map(_("robot")).distinct.flatMap { robot =>
      val mine = fits.filter(_("robot") == robot)
      // the fastest (of equal rates the shorter latency), then the shortest latency (of equal, the faster)
      val fastest = mine.maxByOption(r => (r("samples_per_s").toDouble, -r("latency_ns").toDouble))
      val shortest = mine.minByOption(r => (r("latency_ns").toDouble, -r("samples_per_s").toDouble))
      val fpga = (fastest.toSeq ++ shortest.toSeq).distinct.map { r =>
        val clock =
          if (r("fmax_ecp5_mhz").isEmpty) s"$nominalMhz MHz assumed"
          else s"${r("fmax_ecp5_mhz")} MHz ECP5 proxy"
        Seq(
          robot,
          s"EP4CE30, `${r("schedule")}`",
          rate(r("samples_per_s").toDouble),
          f"${r("latency_ns").toDouble / 1000}%.2f",
          s"${r("clocks_per_sample")} clocks per sample, ${r("latency_cycles")} cycles, $clock; " +
            s"${r("mult_blocks")} blocks, ~${r("est_les")} LEs, ${r("est_m9k")} M9K; max error ${r("max_error_nm")} N·m"
        )
      }
      fpga ++ engines.filter(_("robot") == robot).map { e =>
        Seq(
          robot,
          e("engine"),
          rate(e("calls_per_s").toDouble),
          f"${e("us_per_call").toDouble}%.2f",
          (if (e("operations").isEmpty) "" else s"${e("operations")} operations; ") + e("machine")
        )
      }
    }
    Sweep.table(if (detail) header +: lines else (header +: lines).map(_.take(4)))
  }

  /** Which points a sweep covers: every robot and schedule, or the ones `--robots` and `--schedules` name. */
  final case class Selection(robots: Seq[String], schedules: Seq[String])
  object Selection {
    val all: Selection = Selection(ArmSweep.robots, ArmSweep.schedules.map(_.name))

    /** From comma-separated lists (None: all), each name checked against the sweep's own. */
    def of(robotList: Option[String], scheduleList: Option[String]): Selection = {
      def names(option: String, list: Option[String], known: Seq[String]): Seq[String] = list.fold(known) {
        v =>
          val ns = v.split(",", -1).map(_.trim).toSeq
          ns.find(n => !known.contains(n)).foreach { n =>
            throw new InputError(s"command line: --$option: unknown '$n' (known: ${known.mkString(", ")})")
          }
          known.filter(ns.contains)
      }
      Selection(
        names("robots", robotList, ArmSweep.robots),
        names("schedules", scheduleList, ArmSweep.schedules.map(_.name))
      )
    }
  }

  /** One elaborated point: its rows' JVM-side figures and its Verilog. */
  final case class Design(
      robot: String,
      point: String,
      p: ArmParams,
      errors: IndexedSeq[Double],
      top: String,
      verilog: String
  ) {
    def key: String = s"$robot-$point"

    /** The point as an evaluation job; the manifest names its robot, point and settings. */
    lazy val job: SweepJobs.Point = SweepJobs.Point(
      key,
      top,
      verilog,
      Map(
        "robot" -> robot,
        "point" -> point,
        "settings" -> Map(
          "clocks_per_sample" -> p.schedule.clocksPerSample,
          "storage" -> p.schedule.request.stored.name,
          "max_multipliers" -> p.schedule.request.maxMultipliers,
          "multiplier_units" -> p.schedule.multiplierUnits,
          "internal_frac_bits" -> p.internalFracBits,
          "latency_cycles" -> p.latency
        )
      )
    )
  }

  /** Elaborate the selected points, measuring each distinct fit's errors once. */
  def designs(selection: Selection): Seq[Design] =
    selection.robots.flatMap { robot =>
      val config = ArmGolden.of(robot).head.config
      // Fitted with its own schedule: per-node fraction-bit caps are kept only where they make that schedule cheaper.
      val points =
        schedules
          .filter(s => selection.schedules.contains(s.name))
          .map(point => point.name -> reducerload.compiler.Compiler.arm(point.config(config)))
      // The errors depend on the numerics only: measured once per distinct fit.
      def numericsOf(p: ArmParams) = (p.numerics, p.fracBitLimits)
      val errorsOf =
        points.map(_._2).groupBy(numericsOf).map { case (key, ps) => key -> goldenErrors(ps.head, robot) }
      points.map { case (point, p) =>
        println(s"sweep: elaborating $robot $point (${p.schedule.clocksPerSample} clocks per sample)")
        Design(
          robot,
          point,
          p,
          errorsOf(numericsOf(p)),
          s"ArmDatapath_${p.tag}",
          Emit.withBlackBoxes(
            ChiselStage.emitSystemVerilog(new ArmDatapath(p), Array.empty[String], Emit.firtoolOpts)
          )
        )
      }
    }

  /**
   * Rows from the designs and the evaluation's results, in the designs' order; a point of several seeds gets
   * a row per seed (its schedule named `point-sN`). Failed jobs give no row: they are listed on the terminal.
   */
  def merge(designs: Seq[Design], results: Seq[JobResult], seeds: Seq[Int]): Seq[Row] = {
    val byJob = results.map(r => (r.key, r.seed) -> r.estimate).toMap
    val rows = for {
      d <- designs
      seed <- seeds
      e <- byJob.get((d.key, seed)).flatMap(_.toOption)
    } yield Row(d.robot, if (seeds.size > 1) s"${d.point}-s$seed" else d.point, d.p, d.errors, e)
    results.collect { case JobResult(key, seed, Left(why), _) =>
      println(s"sweep: $key seed $seed failed: $why")
    }
    rows
  }

  /** The columns of cpu.csv the anchors read, and which of them are numbers. */
  private val cpuColumns: Seq[(String, Boolean)] =
    Seq(
      "robot" -> false,
      "engine" -> false,
      "us_per_call" -> true,
      "calls_per_s" -> true,
      "operations" -> false,
      "machine" -> false
    )

  /**
   * The CPU anchors beside a sweep's output (`cpu.csv` in its directory), if there, checked: a missing column
   * or a cell that is not a number is named with its line, as an input error.
   */
  def cpuAnchors(dir: Path): Option[Seq[Seq[String]]] = {
    val file = dir.resolve("cpu.csv")
    Option.when(java.nio.file.Files.exists(file)) {
      val cells = Sweep.cellsOf(
        new String(java.nio.file.Files.readAllBytes(file), java.nio.charset.StandardCharsets.UTF_8)
      )
      def bad(line: Int, what: String) = throw new InputError(s"$file: line $line: $what")
      val header = cells.headOption.getOrElse(bad(1, "empty"))
      cpuColumns.foreach { case (c, _) => if (!header.contains(c)) bad(1, s"no column '$c'") }
      cells.zipWithIndex.tail.foreach { case (row, i) =>
        if (row.size != header.size) bad(i + 1, s"${row.size} cells, the header has ${header.size}")
        cpuColumns.collect { case (c, true) => c }.foreach { c =>
          val v = row(header.indexOf(c))
          if (v.toDoubleOption.forall(x => !(x > 0))) bad(i + 1, s"$c '$v' is not a positive number")
        }
      }
      cells
    }
  }

  /** The sweep's files from its rows: the one writer of arms.csv, arms.md and the plot. */
  def write(out: Path, rows: Seq[Row], fmax: Boolean, command: String): Unit = {
    val cells = header +: rows.map(_.cells)
    val md = markdown(cells, fmax, command, cpuAnchors(out))
    OutputFile.writeAll(out, Seq("arms.csv" -> Sweep.csv(cells), "arms.md" -> md))
    println(md)
    val plot = Seq("python3", "tools/sweep/plot_arms.py", out.resolve("arms.csv").toString, out.toString)
    val status = plot.!
    if (status != 0) println(s"sweep: plot not made (${plot.mkString(" ")} exited $status)")
  }

  /** The sweep's files from the designs and their results, then its summary; a failed job fails the run. */
  def report(
      out: Path,
      designs: Seq[Design],
      results: Seq[JobResult],
      seeds: Seq[Int],
      fmax: Boolean,
      command: String
  ): Unit = {
    write(out, merge(designs, results, seeds), fmax, command)
    SweepJobs.finish(results, out.resolve("arms.csv"))
  }

  /**
   * Elaborate the selection, evaluate it as `evaluation` says (its files in `store/arms/`), write to `out`.
   */
  def run(
      out: Path,
      store: Path,
      fmax: Boolean,
      evaluation: Evaluation,
      command: String,
      selection: Selection = Selection.all,
      seeds: Seq[Int] = Seq(1)
  ): Unit = {
    val ds = designs(selection)
    SweepJobs
      .evaluate(evaluation, store.resolve("arms"), ds.map(_.job), fmax, seeds)
      .foreach(results => report(out, ds, results, seeds, fmax, command))
  }
}
