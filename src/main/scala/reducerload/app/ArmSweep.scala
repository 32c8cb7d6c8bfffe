package reducerload.app

import circt.stage.ChiselStage
import reducerload.arm.{ArmDatapath, ArmGolden, ArmModel, ArmParams}
import reducerload.graph.{ScheduleRequest, Storage}
import reducerload.util.OutputFile

import java.nio.file.Path
import scala.concurrent.duration.Duration
import scala.concurrent.{Await, ExecutionContext, Future}
import scala.sys.process._

/**
 * `run sweep --arms`: every joint of planar3, the UR5 and the Panda (the golden traces' robots and ranges)
 * over the schedule axis, from one operator per operation to one multiplier unit per operand width. Per
 * point: clocks per sample, latency, multiplier blocks, the open-tool estimate (and Fmax proxy with --fmax),
 * samples/s, and per joint the measured max error against Pinocchio over the golden traces (bit-accurate
 * model; the RTL equals it bit for bit, as the tests check) beside the derived bound. Writes arms.csv,
 * arms.md and, with Python + matplotlib, arms_pareto.png.
 */
object ArmSweep {

  /** The clock the samples/s column assumes without the Fmax proxy: the issue's target clock. */
  val nominalMhz: Double = 150.0

  val robots: Seq[String] = Seq("planar3", "ur5", "panda")

  /**
   * The schedule axis: intervals from one clock to hundreds, and the fewest clocks within an EP4CE30's 66
   * blocks; then two of them with the fraction bits fitted to 1e-3 N·m (`numeric.target-error`); then values
   * in block-RAM banks (`schedule.storage = memory`) at 1e-3 N·m from 32 to 512 clocks (88: the UR5 design
   * that meets issue 12's targets; 114: the Panda's, and at 114 with 5 adder units, which the Panda's latency
   * target needs).
   */
  val schedules: Seq[(String, ScheduleRequest, Seq[Double])] =
    Seq(1, 4, 16, 64, 256).map(c => (s"ii$c", ScheduleRequest(clocksPerSample = Some(c)), Nil)) ++ Seq(
      ("budget66", ScheduleRequest(clocksPerSample = None, maxMultipliers = Some(66)), Nil),
      ("budget66-t1e-3", ScheduleRequest(clocksPerSample = None, maxMultipliers = Some(66)), Seq(1e-3)),
      ("ii64-t1e-3", ScheduleRequest(clocksPerSample = Some(64)), Seq(1e-3))
    ) ++
      Seq(32, 64, 88, 114, 128, 512).map(c =>
        (
          s"mem-ii$c-t1e-3",
          ScheduleRequest(clocksPerSample = Some(c), storage = Some(Storage.Memory)),
          Seq(1e-3)
        )
      ) :+
      (
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
  def markdown(cells: Seq[Seq[String]], fmax: Boolean, command: String): String =
    (Seq(
      s"Arm sweep ${if (fmax) "with" else "without"} the ECP5 Fmax proxy. Regenerate: `$command`.",
      s"Latency in ns and samples/s at ${if (fmax) "the Fmax proxy" else s"$nominalMhz MHz"}. Errors: max |torque - Pinocchio| over the golden " +
        "traces per joint (bit-accurate model, equal to the RTL); bound: derived worst case over the declared ranges.",
      "Resources: open-tool Cyclone IV E estimate (tools/estimate/README.md); mult_blocks: the schedule's 18x18 blocks; est_m9k: the estimate's 9-kbit M9K blocks. EP4CE30: 28,848 LEs, 66 multipliers, 66 M9K blocks.",
      ""
    ) ++ Sweep.table(cells)).mkString("", "\n", "\n")

  def run(out: Path, fmax: Boolean, jobs: Int, command: String): Unit = {
    val designs = robots.flatMap { robot =>
      val config = ArmGolden.of(robot).head.config
      // Fitted with its own schedule: per-node fraction-bit caps are kept only where they make that schedule cheaper.
      val points = schedules.map { case (point, request, target) =>
        point -> reducerload.compiler.Compiler.arm(config.copy(targetError = target, schedule = request))
      }
      // The errors depend on the numerics only: measured once per distinct fit.
      def numericsOf(p: ArmParams) = (p.numerics, p.fracBitLimits)
      val errorsOf =
        points.map(_._2).groupBy(numericsOf).map { case (key, ps) => key -> goldenErrors(ps.head, robot) }
      points.map { case (point, p) =>
        val errors = errorsOf(numericsOf(p))
        println(s"sweep: elaborating $robot $point (${p.schedule.clocksPerSample} clocks per sample)")
        val top = s"ArmDatapath_${p.tag}"
        (
          robot,
          point,
          p,
          errors,
          top,
          Emit.withBlackBoxes(
            ChiselStage.emitSystemVerilog(new ArmDatapath(p), Array.empty[String], Emit.firtoolOpts)
          )
        )
      }
    }
    val pool = java.util.concurrent.Executors.newFixedThreadPool(jobs)
    implicit val ec: ExecutionContext = ExecutionContext.fromExecutorService(pool)
    val rows =
      try {
        def measure(d: (String, String, ArmParams, IndexedSeq[Double], String, String)): Row = {
          val (robot, point, p, errors, top, verilog) = d
          val row = Row(robot, point, p, errors, Estimate.run(verilog, top, fmax))
          println(row.cells.mkString("sweep: ", ", ", ""))
          row
        }
        // The first estimate alone: it sets up the tools' virtual environments.
        val first = designs.headOption.map(measure).toSeq
        first ++ Await.result(Future.sequence(designs.drop(1).map(d => Future(measure(d)))), Duration.Inf)
      } finally pool.shutdown()
    val cells = header +: rows.map(_.cells)
    val md = markdown(cells, fmax, command)
    OutputFile.writeAll(out, Seq("arms.csv" -> Sweep.csv(cells), "arms.md" -> md))
    println(md)
    val plot = Seq("python3", "tools/sweep/plot_arms.py", out.resolve("arms.csv").toString, out.toString)
    val status = plot.!
    if (status != 0) println(s"sweep: plot not made (${plot.mkString(" ")} exited $status)")
  }
}
