package example

import chisel3._
import chisel3.util.{Decoupled, Queue, Valid}
import reducerload.api.Core
import reducerload.arm.{ArmDatapath, ArmInput, ArmOutput}
import reducerload.pipeline.MultiplierImpl

/**
 * A design of its own with the reducer-load core inside: a 4-entry FIFO buffers the host's samples for the
 * core (which takes one every `core.clocksPerSample` clocks), and a counter counts the torque sets the core
 * returns.
 */
class ExampleTop(core: Core)(implicit multiplierImpl: MultiplierImpl) extends Module {
  private val arm = core.compiled.arm
  val io = IO(new Bundle {
    val in = Flipped(Decoupled(new ArmInput(arm)))
    val out = Valid(new ArmOutput(arm))
    val results = Output(UInt(32.W))
  })

  private val load = Module(core.module[ArmDatapath])
  load.io.in <> Queue(io.in, 4)
  io.out := load.io.out

  private val results = RegInit(0.U(32.W))
  when(load.io.out.valid)(results := results + 1.U)
  io.results := results
}
