package reducerload.sim

import chisel3._
import chiseltest._
import reducerload.arm.{ArmDatapath, ArmOutputCodes}
import reducerload.graph.SampleCodes

/**
 * The only code that talks to the simulator for ArmDatapath: drive a stimulus, record the outputs.
 * A sample driven while the datapath is not ready is an error of the stimulus, not a silent drop.
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
      Some(ArmOutputCodes(dut.io.out.bits.tau.map(_.peek().litValue).toIndexedSeq, dut.io.out.bits.outOfRange.map(_.peek().litToBoolean).toIndexedSeq))
    else None

  def run(
    dut: ArmDatapath,
    stimulus: Iterator[Cycle[SampleCodes]],
    onOutput: (Long, Option[ArmOutputCodes]) => Unit,
    onDrive: (Long, Cycle[SampleCodes]) => Unit = (_, _) => ()
  ): Long = {
    dut.clock.setTimeout(0)
    stimulus.zipWithIndex.foldLeft(0L) { case (_, (c, cycle)) =>
      c match {
        case Cycle.Reset  => dut.reset.poke(true.B); dut.io.in.valid.poke(false.B)
        case Cycle.Bubble => dut.io.in.valid.poke(false.B)
        case Cycle.Sample(s) =>
          if (!dut.io.in.ready.peek().litToBoolean) throw new IllegalStateException(s"cycle $cycle: sample driven while io_in_ready is low")
          pokeSample(dut, s)
      }
      onOutput(cycle.toLong, peekOutput(dut))
      onDrive(cycle.toLong, c)
      dut.clock.step()
      dut.reset.poke(false.B)
      cycle.toLong + 1
    }
  }
}
