package reducerload.sim.rtl

/**
 * What a stimulus run ([[CompiledHarness.drive]]) does in one clock beyond the quiet default (no new sample,
 * reset low, no host pulse, read address 0); clocks without a record are quiet. `offer`: one more sample
 * becomes available; the harness raises valid with the next available sample whenever it holds none, and
 * holds it (valid high, data unchanged) until valid && ready at a rising edge; valid is low while reset is
 * high. `read`: the host's read address in this clock, whose data comes back one clock later.
 */
final case class ClockStimulus(
    cycle: Long,
    offer: Boolean = false,
    reset: Boolean = false,
    snapshot: Boolean = false,
    clear: Boolean = false,
    read: Option[Int] = None
) {
  require(cycle >= 0, s"stimulus: cycle $cycle is negative")
  read.foreach(a => require(a >= 0, s"stimulus: cycle $cycle: read address $a is negative"))

  def hostAction: Boolean = snapshot || clear || read.nonEmpty

  /** The record's second word in the harness's file: flag bits, the read address in bits 32 to 62. */
  def word: Long =
    (if (offer) 1L else 0L) | (if (reset) 2L else 0L) | (if (snapshot) 4L else 0L) | (if (clear) 8L else 0L) |
      read.fold(0L)(a => 16L | (a.toLong << 32))
}

object ClockStimulus {
  def fromWord(cycle: Long, word: Long): ClockStimulus = ClockStimulus(
    cycle,
    offer = (word & 1) != 0,
    reset = (word & 2) != 0,
    snapshot = (word & 4) != 0,
    clear = (word & 8) != 0,
    read = if ((word & 16) != 0) Some((word >>> 32).toInt) else None
  )
}

/** What a stimulus run saw, in clock order (within a clock: output, snapshotDone, taken, read data). */
sealed trait Observed {
  def cycle: Long
}
object Observed {

  /** A sample was taken (valid && ready) at the rising edge ending `cycle`. */
  final case class Taken(cycle: Long) extends Observed

  /** Output valid in `cycle`, before its rising edge: values in the order of `HarnessPorts.outputs`. */
  final case class Output(cycle: Long, values: IndexedSeq[BigInt]) extends Observed

  /** The host's `snapshotDone` was high in `cycle`. */
  final case class SnapshotDone(cycle: Long) extends Observed

  /** The read data for the address given in `cycle`, as it is one clock later. */
  final case class ReadData(cycle: Long, value: Long) extends Observed

  /** Tags of the harness's file. */
  private[rtl] val takenTag = 0L
  private[rtl] val outputTag = 1L
  private[rtl] val doneTag = 2L
  private[rtl] val readTag = 3L
}
