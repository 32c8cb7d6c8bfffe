package reducerload.sim

/**
 * What a replay found: max |error| per `errorLabels` entry over in-range samples, the samples flagged
 * out of range, the wall-clock seconds of the run (conversion, engine, result lines), the JVM
 * threads' CPU seconds (summed over jobs; on a shared machine the wall clock also counts other
 * work), and for the RTL every harness process's figures.
 */
final case class ReplaySummary(samples: Long, maxErrors: IndexedSeq[Double], outOfRange: Long, seconds: Double, cpuSeconds: Double,
  harness: Seq[HarnessStats]) {
  def samplesPerSecond: Double = samples / seconds.max(1e-9)
  def samplesPerCpuSecond: Double = samples / cpuSeconds.max(1e-9)
  def harnessCycles: Long = harness.map(_.cycles).sum
  /** Clocks per second of harness process wall time (summed over processes), and per second of their CPU time. */
  def cyclesPerHarnessSecond: Double = harnessCycles / harness.map(_.seconds).sum.max(1e-9)
  def cyclesPerHarnessCpuSecond: Double = harnessCycles / harness.map(_.cpuSeconds).sum.max(1e-9)
}
