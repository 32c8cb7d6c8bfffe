package reducerload.sim

/**
 * What a replay found: max |error| per `errorLabels` entry over in-range samples, the samples flagged out of
 * range, the wall-clock seconds of the run (conversion, engine, result lines), the JVM threads' CPU seconds
 * (summed over jobs; on a shared machine the wall clock also counts other work), for the RTL every harness
 * process's figures, and where the replay runs in arrays the time of each of its phases.
 */
final case class ReplaySummary(
    samples: Long,
    maxErrors: IndexedSeq[Double],
    outOfRange: Long,
    seconds: Double,
    cpuSeconds: Double,
    harness: Seq[HarnessStats],
    phases: Option[ReplayPhases] = None
) {
  def samplesPerSecond: Double = samples / seconds.max(1e-9)
  def samplesPerCpuSecond: Double = samples / cpuSeconds.max(1e-9)
  def harnessCycles: Long = harness.map(_.cycles).sum

  /**
   * Clocks per second of harness process wall time (summed over processes), and per second of their CPU time.
   */
  def cyclesPerHarnessSecond: Double = harnessCycles / harness.map(_.seconds).sum.max(1e-9)
  def cyclesPerHarnessCpuSecond: Double = harnessCycles / harness.map(_.cpuSeconds).sum.max(1e-9)
}

/**
 * Wall-clock seconds of a replay's phases, summed over its jobs: the input codes, the engine (the
 * bit-accurate model, or a harness process with its input and output files) and the result lines (the
 * double-precision reference and the text). The engine's figure is what the engine alone takes per sample,
 * apart from the conversion and the file's text around it.
 */
final case class ReplayPhases(codes: Double, engine: Double, lines: Double) {
  def +(o: ReplayPhases): ReplayPhases = ReplayPhases(codes + o.codes, engine + o.engine, lines + o.lines)
}
