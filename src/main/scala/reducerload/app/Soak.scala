package reducerload.app

import chiseltest.RawTester
import chiseltest.simulator.VerilatorBackendAnnotation
import reducerload.arm.{ArmDatapath, ArmModel, ArmOutputCodes, ArmParams, ArmSample}
import reducerload.graph.SampleCodes
import reducerload.sim.rtl.{ArmDriver, Cycle, StreamChecker}
import reducerload.util.InputError

import java.nio.file.{Files, Paths}
import scala.sys.process._
import scala.util.{Random, Try}

/**
 * `run soak`: a long seeded stream through the configured datapath on Verilator, with random bubbles, a few
 * resets, and inputs beyond the declared ranges; every output checked against the bit-accurate model.
 */
object Soak {
  val options: Seq[Opt] = Seq(
    Opt("samples", "N", "samples to stream", "1000000"),
    Opt("seed", "S", "random seed (printed; rerun with it)", "1"),
    Opt("resets", "N", "resets at random points of the stream", "5")
  )

  final case class Result(
      samples: Long,
      cycles: Long,
      checked: Long,
      mismatches: Long,
      examples: Seq[String],
      seconds: Double
  )

  /**
   * Random samples: 1 in 16 with one velocity or acceleration beyond its declared range; bubbles 1 in 8
   * cycles; `resets` resets.
   */
  def stimulus(p: ArmParams, samples: Long, resets: Int, rng: Random): Iterator[Cycle[SampleCodes]] = {
    val model = new ArmModel(p)
    val n = p.numerics
    val joints = p.chain.size
    val resetAt = Seq.fill(resets)((rng.nextDouble() * samples).toLong).toSet
    def within(m: Double) = (2 * rng.nextDouble() - 1) * m
    def sample(): ArmSample = {
      val q = IndexedSeq.fill(joints)(rng.nextDouble() * 8 - 4)
      val qd = Array.tabulate(joints)(j => within(n.velocityLimits(j)))
      val qdd = Array.tabulate(joints)(j => within(n.accelerationLimits(j)))
      if (rng.nextInt(16) == 0) {
        val j = rng.nextInt(joints)
        if (rng.nextBoolean()) qd(j) = 1.5 * n.velocityLimits(j) * qd(j).sign
        else qdd(j) = 1.5 * n.accelerationLimits(j) * qdd(j).sign
      }
      ArmSample(q, qd.toIndexedSeq, qdd.toIndexedSeq)
    }
    Iterator.range(0L, samples).flatMap { i =>
      val bubble = if (rng.nextInt(8) == 0) Iterator(Cycle.Bubble) else Iterator.empty
      val reset = if (resetAt(i)) Iterator(Cycle.Reset, Cycle.Bubble, Cycle.Bubble) else Iterator.empty
      reset ++ bubble ++ Iterator(Cycle.Sample(model.encode(sample())))
    }
  }

  def run(p: ArmParams, samples: Long, seed: Long, resets: Int): Result = {
    val model = new ArmModel(p)
    val checker = new StreamChecker[SampleCodes, ArmOutputCodes](p.latency, model.evaluate)
    val rng = new Random(seed)
    val scratch = Paths.get("target", "soak")
    Files.createDirectories(scratch)
    val dir =
      Paths.get("").toAbsolutePath.relativize(Files.createTempDirectory(scratch.toAbsolutePath, "run-"))
    var result: Option[Result] = None // set once, inside the simulator callback
    try
      RawTester.test(
        new ArmDatapath(p),
        Seq(VerilatorBackendAnnotation, firrtl2.options.TargetDirAnnotation(dir.toString))
      ) { dut =>
        // Samples wait while the datapath is busy (ready low between its one-in-II input clocks).
        val stim = stimulus(p, samples, resets, rng) ++ Iterator.fill(p.latency + 2)(Cycle.Bubble)
        val start = System.nanoTime()
        val cycles = ArmDriver.run(
          dut,
          stim,
          (cycle, out) => checker.observe(cycle, out),
          (cycle, c) => checker.drive(cycle, c),
          holdUntilReady = true
        )
        result = Some(
          Result(
            samples,
            cycles,
            checker.checked,
            checker.mismatches,
            checker.examples,
            (System.nanoTime() - start) / 1e9
          )
        )
      }
    finally Try(Seq("rm", "-rf", dir.toString).!)
    result.get
  }

  def main(cli: Cli): Unit = {
    def number(name: String, default: Long): Long = cli
      .get(name)
      .map { v =>
        Try(v.toLong)
          .filter(_ >= 0)
          .getOrElse(throw new InputError(s"command line: --$name must be a non-negative integer, got '$v'"))
      }
      .getOrElse(default)
    val samples = number("samples", 1000000L)
    val seed = number("seed", 1L)
    val resets = number("resets", 5L).toInt
    if (!reducerload.sim.rtl.VerilatorHarness.available)
      throw new InputError("soak needs Verilator on the PATH (Debian: apt-get install verilator)")
    val c = cli.compiled
    println(
      s"soak: $samples samples, seed $seed, $resets resets, bubbles 1 in 8, 1 in 16 samples beyond the declared ranges"
    )
    val r = run(c.arm, samples, seed, resets)
    println(
      f"soak: ${r.checked} outputs checked bit-exact against the model over ${r.cycles} cycles, ${r.mismatches} mismatches, " +
        f"${r.samples / r.seconds}%.0f samples/s (Verilator)"
    )
    if (r.mismatches > 0)
      throw new IllegalStateException(
        r.examples.mkString(s"soak: ${r.mismatches} mismatches, first ones:\n", "\n", "")
      )
  }
}
