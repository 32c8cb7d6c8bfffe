package reducerload.sim

import chisel3._
import chiseltest._

/**
 * Drives a ready/valid pipeline cycle by cycle through chiseltest: the one loop every design's
 * driver shares. A sample driven while `ready` is low is an error of the stimulus (space it with
 * [[Stream.spaced]]), not a silent drop.
 */
final case class StreamDriver[I, O](clock: Clock, reset: Reset, inValid: Bool, inReady: Bool, poke: I => Unit, peek: () => Option[O]) {

  /** Drive `stimulus`, report each cycle's output (before the edge) and what was driven; returns the cycles run. */
  def run(stimulus: Iterator[Cycle[I]], onOutput: (Long, Option[O]) => Unit, onDrive: (Long, Cycle[I]) => Unit = (_: Long, _: Cycle[I]) => ()): Long = {
    clock.setTimeout(0)
    stimulus.zipWithIndex.foldLeft(0L) { case (_, (c, cycle)) =>
      c match {
        case Cycle.Reset  => reset.poke(true.B); inValid.poke(false.B)
        case Cycle.Bubble => inValid.poke(false.B)
        case Cycle.Sample(s) =>
          if (!inReady.peek().litToBoolean) throw new IllegalStateException(s"cycle $cycle: sample driven while io_in_ready is low")
          inValid.poke(true.B)
          poke(s)
      }
      onOutput(cycle.toLong, peek())
      onDrive(cycle.toLong, c)
      clock.step()
      reset.poke(false.B)
      cycle.toLong + 1
    }
  }
}
