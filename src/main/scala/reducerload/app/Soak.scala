package reducerload.app

import chiseltest.RawTester
import chiseltest.simulator.VerilatorBackendAnnotation
import reducerload.load._
import reducerload.sim.{Cycle, LoadDriver, Stream, StreamChecker}
import reducerload.trace.InputError

import java.nio.file.{Files, Paths}
import scala.sys.process._
import scala.util.{Random, Try}

/**
 * `run soak`: a long seeded stream through LoadDatapath on Verilator, with random bubbles, a few
 * resets, and inputs beyond the declared ranges; every output checked against the bit-accurate model.
 */
object Soak {
  val options: Seq[Opt] = Seq(
    Opt("samples", "N", "samples to stream", "1000000"),
    Opt("seed", "S", "random seed (printed; rerun with it)", "1"),
    Opt("resets", "N", "resets at random points of the stream", "5")
  )

  final case class Result(samples: Long, cycles: Long, checked: Long, mismatches: Long, examples: Seq[String], seconds: Double)

  /** Random samples: 1 in 16 beyond its declared range; bubbles 1 in 8 cycles; `resets` resets. */
  def stimulus(p: LoadParams, samples: Long, resets: Int, rng: Random): Iterator[Cycle[LoadInputCodes]] = {
    val model = new LoadDatapathModel(p)
    val resetAt = Seq.fill(resets)((rng.nextDouble() * samples).toLong).toSet
    def sample(): JointSample = {
      val r = p.robot
      def within(m: Double) = (2 * rng.nextDouble() - 1) * m
      val s = Array(rng.nextDouble() * 8 - 4, rng.nextDouble() * 8 - 4, rng.nextDouble() * 8 - 4,
        within(r.maxVelocity(0)), within(r.maxVelocity(1)), within(r.maxVelocity(2)),
        within(r.maxAcceleration(0)), within(r.maxAcceleration(1)), within(r.maxAcceleration(2)))
      if (rng.nextInt(16) == 0) { val i = 3 + rng.nextInt(6); s(i) = s(i).sign * (if (i < 6) r.maxVelocity(i - 3) else r.maxAcceleration(i - 6)) * 1.5 }
      JointSample.fromSeq(s.toSeq)
    }
    Iterator.range(0L, samples).flatMap { i =>
      val bubble = if (rng.nextInt(8) == 0) Iterator(Cycle.Bubble) else Iterator.empty
      val reset = if (resetAt(i)) Iterator(Cycle.Reset, Cycle.Bubble, Cycle.Bubble) else Iterator.empty
      reset ++ bubble ++ Iterator(Cycle.Sample(model.encode(sample())))
    }
  }

  def run(p: LoadParams, samples: Long, seed: Long, resets: Int): Result = {
    val model = new LoadDatapathModel(p)
    val checker = new StreamChecker[LoadInputCodes, LoadOutputCodes](LoadDatapath.latency(p), model.evaluate)
    val rng = new Random(seed)
    val scratch = Paths.get("target", "soak")
    Files.createDirectories(scratch)
    val dir = Paths.get("").toAbsolutePath.relativize(Files.createTempDirectory(scratch.toAbsolutePath, "run-"))
    var result: Option[Result] = None // set once, inside the simulator callback
    try {
      RawTester.test(new LoadDatapath(p), Seq(VerilatorBackendAnnotation, firrtl2.options.TargetDirAnnotation(dir.toString))) { dut =>
        val stim = Stream.spaced(stimulus(p, samples, resets, rng), p.samplePeriod) ++ Iterator.fill(dut.latency + 2)(Cycle.Bubble)
        val start = System.nanoTime()
        val cycles = LoadDriver.run(dut, stim, (cycle, out) => checker.observe(cycle, out), (cycle, c) => checker.drive(cycle, c))
        result = Some(Result(samples, cycles, checker.checked, checker.mismatches, checker.examples, (System.nanoTime() - start) / 1e9))
      }
    } finally Try(Seq("rm", "-rf", dir.toString).!)
    result.get
  }

  def main(cli: Cli): Unit = {
    def number(name: String, default: Long): Long = cli.get(name).map { v =>
      Try(v.toLong).filter(_ >= 0).getOrElse(throw new InputError(s"command line: --$name must be a non-negative integer, got '$v'"))
    }.getOrElse(default)
    val samples = number("samples", 1000000L)
    val seed = number("seed", 1L)
    val resets = number("resets", 5L).toInt
    if (Try(Seq("verilator", "--version").!!(ProcessLogger(_ => ()))).isFailure)
      throw new InputError("soak needs Verilator on the PATH (Debian: apt-get install verilator)")
    val p = cli.params
    println(s"soak: $samples samples, seed $seed, $resets resets, bubbles 1 in 8, 1 in 16 samples beyond the declared ranges")
    val r = run(p, samples, seed, resets)
    println(f"soak: ${r.checked} outputs checked bit-exact against the model over ${r.cycles} cycles, ${r.mismatches} mismatches, " +
      f"${r.samples / r.seconds}%.0f samples/s (Verilator)")
    if (r.mismatches > 0) throw new IllegalStateException(r.examples.mkString(s"soak: ${r.mismatches} mismatches, first ones:\n", "\n", ""))
  }
}
