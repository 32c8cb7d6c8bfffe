package reducerload.graph

import reducerload.pipeline.MemoryDelay

/**
 * How a value of a shared registers datapath (2 clocks per sample or more) reaches the cycles it is read in.
 * Its first register is written once per sample, in the cycle before it is ready, and holds it for the
 * interval; a read k intervals later takes the k-th register of a chain written at the same phase or, when k
 * intervals are `datapath.memory-delay-min-cycles` clocks or more, a block-RAM delay of the first register by
 * k intervals ([[reducerload.pipeline.MemoryDelay]]): the chain shifts once per interval whatever the
 * samples, so the delayed register gives the same word in every cycle, in an M9K instead of k registers.
 *
 * @param chain
 *   registers after the first (the deepest stage read from registers)
 * @param delayed
 *   the stages read from block-RAM delays, each a delay of that many intervals
 */
final case class HeldTaps(chain: Int, delayed: Seq[Int]) {

  /** Registers of the value: its first register and its chain. */
  def registers: Int = chain + 1

  /** Register bits of a value of `width` bits. */
  def registerBits(width: Int): Long = registers.toLong * width
}

object HeldTaps {

  /**
   * The taps of a value ready in cycle `ready` and read in `reads`, at `interval` clocks per sample;
   * `memoryMinCycles` 0 keeps every stage in registers.
   */
  def apply(interval: Int, ready: Int, reads: Seq[Int], memoryMinCycles: Int): HeldTaps = {
    require(interval >= 2, s"HeldTaps: at $interval clock per sample values wait in delay lines")
    val stages = reads.map(r => (r - ready) / interval).distinct.sorted
    val (delayed, chained) =
      stages.partition(k => k >= 1 && MemoryDelay.inBlockRam(k * interval, memoryMinCycles))
    HeldTaps(chained.maxOption.getOrElse(0), delayed)
  }
}
