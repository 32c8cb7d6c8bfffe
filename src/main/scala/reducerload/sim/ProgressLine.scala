package reducerload.sim

import java.io.PrintStream
import java.util.concurrent.atomic.{AtomicBoolean, AtomicLong}

/**
 * Samples done, rate and time left of a long run, on one line rewritten at most once a second. Thread-safe:
 * chunks finishing on several threads call [[advance]]. Quiet when `out` is None.
 */
final class ProgressLine(total: Long, what: String, out: Option[PrintStream]) {
  private val start = System.nanoTime()
  private val done = new AtomicLong
  private val lastShown = new AtomicLong(start)
  private val shown = new AtomicBoolean(false) // whether a line needs clearing at the end

  def advance(samples: Long): Unit = {
    val now = System.nanoTime()
    val d = done.addAndGet(samples)
    val last = lastShown.get
    if (out.isDefined && now - last >= 1000000000L && lastShown.compareAndSet(last, now)) out.foreach { o =>
      val rate = d / ((now - start) / 1e9)
      val left = if (rate > 0) (total - d) / rate else 0.0
      o.print(f"\r$what: $d%d of $total%d samples, $rate%.0f samples/s, ${left}%.0f s left   ")
      o.flush()
      shown.set(true)
    }
  }

  /** Clear the line, so the summary that follows starts clean. */
  def finish(): Unit = if (shown.get) out.foreach { o => o.print("\r" + " " * 100 + "\r"); o.flush() }
}

object ProgressLine {

  /** On a terminal only: a redirected or piped run (a log, a test) stays quiet. */
  def onTerminal(total: Long, what: String): ProgressLine =
    new ProgressLine(total, what, if (System.console() != null) Some(System.out) else None)
}
