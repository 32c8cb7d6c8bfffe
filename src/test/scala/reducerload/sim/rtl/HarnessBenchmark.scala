package reducerload.sim.rtl

import reducerload.testutil.CompiledParams
import reducerload.app.{Emit, Top}
import reducerload.config.LoadParams
import reducerload.load.LoadChecks

import scala.util.Random

/**
 * By hand, not a test: samples per second of the compiled harness on random samples of the default design,
 * with and without the build; `--fresh` builds into an empty cache instead of reusing one: ./sbt
 * "Test/runMain reducerload.sim.rtl.HarnessBenchmark 1000000 --fresh"
 */
object HarnessBenchmark {
  def main(args: Array[String]): Unit = {
    val n = args.find(_.forall(_.isDigit)).map(_.toInt).getOrElse(1000000)
    val cache =
      if (args.contains("--fresh")) java.nio.file.Files.createTempDirectory("harness-benchmark-cache-")
      else VerilatorHarness.cacheRoot
    require(n >= 1, s"sample count must be >= 1, got $n")
    val p = LoadParams.default
    val model = new LoadChecks.Joint3Model(p)
    val rng = new Random(7L)
    val codes = IndexedSeq.fill(n)(model.encode(LoadChecks.randomSample(p.robot, rng)))
    val inputs = codes.map(ArmHarnessPorts.values)
    val verilog =
      Emit.emit(reducerload.compiler.Compiler.compile(p, "benchmark"), Top.Load, "benchmark").verilog

    val compileStart = System.nanoTime()
    val harness = VerilatorHarness.compile(verilog, p.arm.moduleName, ArmHarnessPorts(p.arm), cache)
    val compileSeconds = (System.nanoTime() - compileStart) / 1e9

    val runStart = System.nanoTime()
    val r =
      harness.run(inputs, samplePeriod = p.arm.schedule.clocksPerSample, drainCycles = p.arm.latency + 1)
    val runSeconds = (System.nanoTime() - runStart) / 1e9
    require(r.outputs.size == n, s"${r.outputs.size} outputs for $n samples")
    val checked = 10000.min(n)
    val wrong =
      (0 until checked).count(i => ArmHarnessPorts.codes(r.outputs(i), 1) != model.evaluate(codes(i)))
    require(wrong == 0, s"$wrong of the first $checked outputs differ from the model")

    println(
      f"[benchmark] $n samples, default preset, ${r.stats.cycles} cycles; first $checked bit-exact with the model"
    )
    println(
      f"[benchmark] build: $compileSeconds%.1f s (${if (harness.fromCache) "cache hit" else "fresh build"}) in ${harness.directory}"
    )
    println(
      f"[benchmark] simulator process alone: ${r.stats.seconds}%.2f s = ${r.stats.samplesPerSecond}%.0f samples/s " +
        f"(${r.stats.cpuSeconds}%.2f CPU s = ${r.stats.cyclesPerCpuSecond}%.0f clocks per CPU second)"
    )
    println(
      f"[benchmark] run (files, process, decoding): $runSeconds%.2f s = ${n / runSeconds}%.0f samples/s excluding the build"
    )
    if (args.contains("--fresh")) VerilatorHarness.deleteTree(cache)
    println(
      f"[benchmark] with the build: ${compileSeconds + runSeconds}%.2f s = ${n / (compileSeconds + runSeconds)}%.0f samples/s"
    )
  }
}
