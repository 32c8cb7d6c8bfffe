package reducerload.regmap

import chisel3._

/**
 * An Avalon-MM slave (Avalon Interface Specifications, memory-mapped interfaces): word `address` (the
 * interconnect turns the master's byte address into the slave's word address), `read`, `write`, 32-bit
 * `writedata` and `readdata`, and `readdatavalid` (pipelined reads of variable latency; here always one
 * clock: `readdata` is valid with `readdatavalid` in the cycle after `read`). No `waitrequest`: every
 * transfer is taken at once. Reads have no side effects.
 */
class AvalonSlave(addressBits: Int) extends Bundle {
  val address = Input(UInt(addressBits.W))
  val read = Input(Bool())
  val write = Input(Bool())
  val writedata = Input(UInt(CsrMap.dataBits.W))
  val readdata = Output(UInt(CsrMap.dataBits.W))
  val readdatavalid = Output(Bool())
}
