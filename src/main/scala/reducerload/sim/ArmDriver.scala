package reducerload.sim

import chisel3._
import chiseltest._
import reducerload.arm.{ArmDatapath, ArmOutputCodes}
import reducerload.graph.SampleCodes

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
