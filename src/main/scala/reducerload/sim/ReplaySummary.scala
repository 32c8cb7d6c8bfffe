package reducerload.sim

/**
 * What a replay found: max |error| per `errorLabels` entry over in-range samples, the samples flagged
 * out of range, the wall-clock seconds of the run (conversion, engine, result lines), and for the RTL
 * the clocks simulated and the seconds spent in harness processes (summed over processes), and the
 * JVM threads' CPU seconds (summed over jobs; on a shared machine the wall clock also counts other work).
 */
final case class ReplaySummary(samples: Long, maxErrors: IndexedSeq[Double], outOfRange: Long, seconds: Double,
  harnessCycles: Long, harnessSeconds: Double, cpuSeconds: Double) {
  def samplesPerSecond: Double = samples / seconds.max(1e-9)
  def samplesPerCpuSecond: Double = samples / cpuSeconds.max(1e-9)
  def cyclesPerHarnessSecond: Double = harnessCycles / harnessSeconds.max(1e-9)
}
