package reducerload.sim

/**
 * What one harness run did: samples taken, valid outputs, clock cycles after reset, the simulator process's
 * wall time (start-up and file I/O included) and its CPU time (what it takes on a core of its own; on a
 * shared machine the wall time also counts other work).
 */
final case class HarnessStats(
    samples: Long,
    outputs: Long,
    cycles: Long,
    seconds: Double,
    cpuSeconds: Double
) {
  def samplesPerSecond: Double = samples / seconds.max(1e-9)
  def cyclesPerCpuSecond: Double = cycles / cpuSeconds.max(1e-9)
}
