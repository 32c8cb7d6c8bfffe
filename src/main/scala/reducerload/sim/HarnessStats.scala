package reducerload.sim

/** What one harness run did: samples taken, valid outputs, clock cycles after reset, and the simulator's wall time. */
final case class HarnessStats(samples: Long, outputs: Long, cycles: Long, seconds: Double) {
  def samplesPerSecond: Double = samples / seconds.max(1e-9)
}
