package reducerload.sim.rtl

import chisel3._
import chiseltest._
import scala.annotation.tailrec
import reducerload.arm.{ArmDatapath, ArmOutputCodes}
import reducerload.graph.SampleCodes

/**
 * Drives a ready/valid pipeline cycle by cycle through chiseltest: the one loop every design's driver shares.
 * A sample driven while `ready` is low is an error of the stimulus (space it with [[Stream.spaced]]), not a
 * silent drop; with `holdUntilReady` it is offered again every clock until the design takes it
 * (back-pressure), and those clocks are reported as bubbles, since nothing entered.
 */
final case class StreamDriver[I, O](
    clock: Clock,
    reset: Reset,
    inValid: Bool,
    inReady: Bool,
    poke: I => Unit,
    peek: () => Option[O]
) {

  /**
   * Drive `stimulus`, report each cycle's output (before the edge) and what entered the design; returns the
   * cycles run.
   */
  def run(
      stimulus: Iterator[Cycle[I]],
      onOutput: (Long, Option[O]) => Unit,
      onDrive: (Long, Cycle[I]) => Unit = (_: Long, _: Cycle[I]) => (),
      holdUntilReady: Boolean = false
  ): Long = {
    clock.setTimeout(0)
    @tailrec def loop(cycle: Long, pending: Option[Cycle[I]]): Long =
      pending.orElse(stimulus.nextOption()) match {
        case None => cycle
        case Some(c) =>
          val (entered, held) = c match {
            case Cycle.Reset  => reset.poke(true.B); inValid.poke(false.B); (c, None)
            case Cycle.Bubble => inValid.poke(false.B); (c, None)
            case Cycle.Sample(s) =>
              val ready = inReady.peek().litToBoolean
              if (!ready && !holdUntilReady)
                throw new IllegalStateException(s"cycle $cycle: sample driven while io_in_ready is low")
              inValid.poke(true.B)
              poke(s)
              if (ready) (c, None) else (Cycle.Bubble, Some(c))
          }
          onOutput(cycle, peek())
          onDrive(cycle, entered)
          clock.step()
          reset.poke(false.B)
          loop(cycle + 1, held)
      }
    loop(0L, None)
  }
}

/**
 * The only code that talks to the simulator for ArmDatapath: drive a stimulus, record the outputs. A sample
 * driven while the datapath is not ready is an error of the stimulus, not a silent drop.
 */
object ArmDriver {

  def pokeSample(dut: ArmDatapath, s: SampleCodes): Unit = {
    dut.io.in.valid.poke(true.B)
    s.angles.zip(dut.io.in.bits.q).foreach { case (v, port) => port.poke(v.U) }
    s.velocities.zip(dut.io.in.bits.qd).foreach { case (v, port) => port.poke(v.S) }
    s.accelerations.zip(dut.io.in.bits.qdd).foreach { case (v, port) => port.poke(v.S) }
  }

  def peekOutput(dut: ArmDatapath): Option[ArmOutputCodes] =
    if (dut.io.out.valid.peek().litToBoolean)
      Some(
        ArmOutputCodes(
          dut.io.out.bits.tau.map(_.peek().litValue).toIndexedSeq,
          dut.io.out.bits.outOfRange.map(_.peek().litToBoolean).toIndexedSeq
        )
      )
    else None

  def run(
      dut: ArmDatapath,
      stimulus: Iterator[Cycle[SampleCodes]],
      onOutput: (Long, Option[ArmOutputCodes]) => Unit,
      onDrive: (Long, Cycle[SampleCodes]) => Unit = (_, _) => (),
      holdUntilReady: Boolean = false
  ): Long =
    StreamDriver[SampleCodes, ArmOutputCodes](
      dut.clock,
      dut.reset,
      dut.io.in.valid,
      dut.io.in.ready,
      pokeSample(dut, _),
      () => peekOutput(dut)
    )
      .run(stimulus, onOutput, onDrive, holdUntilReady)
}
