package reducerload.sim

import scala.collection.mutable

/**
 * Checks a fixed-latency pipeline's outputs on the fly, for streams too long to hold in memory: the output
 * observed in cycle t must be the sample driven in cycle t - latency, unless a reset came in between (then
 * valid must be low). Drops, duplicates and misalignment all show up as a mismatch. Same rule as
 * [[Stream.expected]], in constant memory.
 */
final class StreamChecker[A, B](
    latency: Int,
    expect: A => B,
    same: (B, B) => Boolean = (a: B, b: B) => a == b
) {
  private val inFlight = mutable.Queue.empty[(Long, A)]
  private val firstMismatches = mutable.ArrayBuffer.empty[String]
  private var mismatchCount = 0L // counters of a running check, not elaboration state
  private var checkedCount = 0L

  def mismatches: Long = mismatchCount
  def checked: Long = checkedCount
  def examples: Seq[String] = firstMismatches.toSeq

  /** Record what was driven in `cycle` (before the clock edge). */
  def drive(cycle: Long, c: Cycle[A]): Unit = c match {
    case Cycle.Reset     => inFlight.clear()
    case Cycle.Bubble    => ()
    case Cycle.Sample(a) => inFlight.enqueue(cycle -> a)
  }

  /**
   * Check what was observed in `cycle` (before the clock edge, so before this cycle's drive takes effect).
   */
  def observe(cycle: Long, out: Option[B]): Unit = {
    val expected =
      if (inFlight.nonEmpty && inFlight.head._1 == cycle - latency) Some(expect(inFlight.dequeue()._2))
      else None
    val ok = (expected, out) match {
      case (None, None)       => true
      case (Some(e), Some(o)) => checkedCount += 1; same(e, o)
      case _                  => false
    }
    if (!ok) {
      mismatchCount += 1
      if (firstMismatches.size < 10) firstMismatches += s"cycle $cycle: expected $expected, observed $out"
    }
  }
}
