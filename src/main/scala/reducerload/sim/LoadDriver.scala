package reducerload.sim

import chisel3._
import chiseltest._
import reducerload.load.{LoadDatapath, LoadInputCodes, LoadOutputCodes}

/** One clock cycle of stimulus for a streaming pipeline. */
sealed trait Cycle[+A]
object Cycle {
  final case class Sample[A](value: A) extends Cycle[A]
  case object Bubble extends Cycle[Nothing]
  case object Reset extends Cycle[Nothing]
}

/**
 * The only code that talks to the simulator for LoadDatapath: drive a stimulus, record the outputs.
 * A sample driven while the datapath is not ready is an error of the stimulus (space it with
 * [[Stream.spaced]]), not a silent drop.
 */
object LoadDriver {

  /** Put one sample on the input port (valid high). */
  def pokeSample(dut: LoadDatapath, s: LoadInputCodes): Unit = {
    dut.io.in.valid.poke(true.B)
    dut.io.in.bits.t1.poke(s.t1.U)
    dut.io.in.bits.t2.poke(s.t2.U)
    dut.io.in.bits.t3.poke(s.t3.U)
    dut.io.in.bits.d1.poke(s.d(0).S)
    dut.io.in.bits.d2.poke(s.d(1).S)
    dut.io.in.bits.d3.poke(s.d(2).S)
    dut.io.in.bits.dd1.poke(s.dd(0).S)
    dut.io.in.bits.dd2.poke(s.dd(1).S)
    dut.io.in.bits.dd3.poke(s.dd(2).S)
  }

  /** The output port this cycle. */
  def peekOutput(dut: LoadDatapath): Option[LoadOutputCodes] =
    if (dut.io.out.valid.peek().litToBoolean)
      Some(LoadOutputCodes(dut.io.out.bits.load.peek().litValue, dut.io.out.bits.outOfRange.peek().litToBoolean))
    else None

  def run(
    dut: LoadDatapath,
    stimulus: Iterator[Cycle[LoadInputCodes]],
    onOutput: (Long, Option[LoadOutputCodes]) => Unit,
    onDrive: (Long, Cycle[LoadInputCodes]) => Unit = (_, _) => ()
  ): Long =
    StreamDriver[LoadInputCodes, LoadOutputCodes](dut.clock, dut.reset, dut.io.in.valid, dut.io.in.ready, pokeSample(dut, _), () => peekOutput(dut))
      .run(stimulus, onOutput, onDrive)
}
