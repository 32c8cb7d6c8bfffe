package reducerload.app

import reducerload.compiler.Compiled
import reducerload.sim.replay.ArmReplay
import reducerload.sim.rtl.{CompiledHarness, HarnessStats, Observed, VerilatorHarness}
import reducerload.util.InputError

import scala.util.Try

/**
 * `run soak`: a long seeded stream through the emitted design (`ArmDatapath`, or `MonitoredArm` with
 * `monitor.enabled`) on the compiled Verilator harness of `run simulate` (same Verilog, same cache): bubbles,
 * every sample held valid until taken, resets, samples beyond the declared ranges and, with a monitor,
 * snapshots, clears and reads at random clocks ([[SoakPlan]]); every output, every take and every word read
 * checked against the bit-accurate models ([[SoakCheck]]). The plan and the check are plain Scala; only
 * [[simulate]] talks to a simulator.
 */
object Soak {
  val options: Seq[Opt] = Seq(
    Opt("samples", "N", "samples to stream", "1000000"),
    Opt("seed", "S", "random seed (printed; rerun with it)", "1"),
    Opt("resets", "N", "resets at random points of the stream", "100")
  )

  final case class Result(
      plan: SoakPlan,
      taken: Long,
      outputs: Long,
      flagged: Long,
      reads: Long,
      snapshots: Long,
      mismatches: Long,
      examples: Seq[String],
      harness: HarnessStats,
      seconds: Double
  )

  /**
   * The compiled harness of `c`'s design, from exactly the Verilog `run simulate` compiles (shared cache).
   */
  def harness(c: Compiled): CompiledHarness = {
    val emission = Emit.emit(Emit.bare(c), Top.Load, Simulate.emitCommand)
    VerilatorHarness.compile(emission.verilog, emission.topModule, new ArmReplay(c.arm, c.monitor).ports)
  }

  /** Run `plan` on `harness`; what the design did goes to `onObserved`, in clock order. */
  def simulate(harness: CompiledHarness, plan: SoakPlan)(onObserved: Observed => Unit): HarnessStats =
    harness.drive(plan.inputs, plan.events, plan.cycles)(onObserved)

  /** Simulate `plan` and check every observation (each also given to `seen`, for tests). */
  def run(harness: CompiledHarness, plan: SoakPlan, seen: Observed => Unit = _ => ()): Result = {
    val start = System.nanoTime()
    val check = new SoakCheck(plan, plan.expected)
    val stats = simulate(harness, plan) { o => seen(o); check.observe(o) }
    check.finish()
    Result(
      plan,
      check.samplesTaken.toLong,
      check.outputs,
      check.flagged,
      check.readsChecked,
      check.snapshotsSeen,
      check.mismatches,
      check.examples,
      stats,
      (System.nanoTime() - start) / 1e9
    )
  }

  /** The lines `run soak` prints for `r`. */
  def report(r: Result): Seq[String] = {
    val p = r.plan
    Seq(
      f"soak: seed ${p.seed}: ${p.samples} samples in ${r.harness.cycles} clocks (${p.p.schedule.clocksPerSample} per sample, " +
        f"latency ${p.p.latency}), ${p.resets} resets" + p.monitor.fold("")(_ =>
          s", ${p.snapshots} snapshots, ${p.clears} clears, ${p.reads} reads"
        ),
      f"soak: ${r.taken} samples taken, ${r.outputs} outputs (${r.flagged} flagged out of range)" +
        p.monitor.fold("")(_ => s", ${r.snapshots} snapshots done, ${r.reads} words read") +
        s": ${r.mismatches} mismatches with the bit-accurate model",
      f"soak: ${r.seconds}%.1f s (simulator ${r.harness.seconds}%.1f s, ${r.harness.cyclesPerCpuSecond}%.0f clocks per CPU second), " +
        f"${p.samples / r.seconds}%.0f samples/s"
    ) ++ r.examples.map("soak: mismatch: " + _)
  }

  def main(cli: Cli): Unit = {
    def number(name: String, default: Long, max: Long): Long = cli
      .get(name)
      .map { v =>
        Try(v.toLong)
          .filter(x => x >= 0 && x <= max)
          .getOrElse(
            throw new InputError(s"command line: --$name must be an integer from 0 to $max, got '$v'")
          )
      }
      .getOrElse(default)
    val samples = number("samples", 1000000L, Int.MaxValue / 64).toInt
    val seed = number("seed", 1L, Long.MaxValue)
    val resets = number("resets", 100L, samples.toLong).toInt
    if (samples < 1) throw new InputError("command line: --samples must be at least 1")
    if (!VerilatorHarness.available)
      throw new InputError("soak needs Verilator on the PATH (Debian: apt-get install verilator)")
    val c = cli.compiled
    val planStart = System.nanoTime()
    val plan = SoakPlan(c.arm, c.monitor, SoakRates(samples, resets), seed)
    println(
      f"soak: seed $seed, ${if (c.monitor.nonEmpty) "monitored arm" else "arm datapath"}, $samples samples planned " +
        f"in ${(System.nanoTime() - planStart) / 1e9}%.1f s"
    )
    val h = harness(c)
    println(s"soak: harness ${h.directory}${if (h.fromCache) " (cached)" else ""}")
    val r = run(h, plan)
    report(r).foreach(println)
    if (r.mismatches > 0)
      throw new IllegalStateException(
        s"soak: ${r.mismatches} mismatches with the bit-accurate model (seed $seed)"
      )
  }
}
