package reducerload.sim.rtl

/** One clock cycle of stimulus for a streaming pipeline. */
sealed trait Cycle[+A]
object Cycle {
  final case class Sample[A](value: A) extends Cycle[A]
  case object Bubble extends Cycle[Nothing]
  case object Reset extends Cycle[Nothing]
}

/**
 * What a pipeline of fixed latency must show, cycle by cycle, for a stimulus: the output observed in cycle t
 * is the sample driven in cycle t - latency, unless a reset was applied in between, in which case valid is
 * low. Plain Scala, independent of any simulator.
 */
object Stream {

  def expected[A](stimulus: IndexedSeq[Cycle[A]], latency: Int): IndexedSeq[Option[A]] =
    stimulus.indices.map { t =>
      val c = t - latency
      if (c < 0) None
      else
        stimulus(c) match {
          case Cycle.Sample(v) if !(c until t).exists(k => stimulus(k) == Cycle.Reset) => Some(v)
          case _                                                                       => None
        }
    }

  /** Compare observed outputs with expectations; returns human-readable mismatches (first `limit`). */
  def mismatches[A, B](
      expected: IndexedSeq[Option[A]],
      observed: IndexedSeq[Option[B]],
      same: (A, B) => Boolean,
      limit: Int = 10
  ): Seq[String] = {
    require(expected.size == observed.size, s"expected ${expected.size} cycles, observed ${observed.size}")
    expected.indices.iterator
      .filter { t =>
        (expected(t), observed(t)) match {
          case (None, None)       => false
          case (Some(e), Some(o)) => !same(e, o)
          case _                  => true
        }
      }
      .take(limit)
      .map(t => s"cycle $t: expected ${expected(t)}, observed ${observed(t)}")
      .toSeq
  }

  /**
   * The stimulus for a pipeline that takes one sample every `period` clocks: `period - 1` bubbles after every
   * sample; bubbles and resets pass through. Lazy, for long streams.
   */
  def spaced[A](stimulus: Iterator[Cycle[A]], period: Int): Iterator[Cycle[A]] = {
    require(period >= 1, s"spaced: period must be >= 1, got $period")
    stimulus.flatMap {
      case s: Cycle.Sample[A] @unchecked => Iterator(s) ++ Iterator.fill(period - 1)(Cycle.Bubble)
      case other                         => Iterator(other)
    }
  }

  /** Random stimulus: samples with bubbles (probability `bubble`) and occasional resets. */
  def randomStimulus[A](
      rng: scala.util.Random,
      samples: IndexedSeq[A],
      bubble: Double,
      resets: Int
  ): IndexedSeq[Cycle[A]] = {
    val withBubbles = samples.flatMap { s =>
      if (rng.nextDouble() < bubble) Seq(Cycle.Bubble, Cycle.Sample(s)) else Seq(Cycle.Sample(s))
    }
    val resetAt = Seq.fill(resets)(rng.nextInt(withBubbles.size.max(1))).toSet
    withBubbles.zipWithIndex.flatMap { case (c, i) => if (resetAt(i)) Seq(Cycle.Reset, c) else Seq(c) }
  }
}
