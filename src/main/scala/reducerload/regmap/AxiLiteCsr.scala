package reducerload.regmap

import chisel3._
import chisel3.util.{Decoupled, DecoupledIO}
import reducerload.arm.{ArmIO, ArmParams}
import reducerload.monitor.MonitorParams
import reducerload.pipeline.MultiplierImpl

/** AXI4-Lite write address, write data, write response, read address and read data channels (32-bit data). */
class AxiLiteSlave(addressBits: Int) extends Bundle {
  val aw = Flipped(Decoupled(UInt(addressBits.W)))
  val w = Flipped(Decoupled(new Bundle {
    val data = UInt(CsrMap.dataBits.W)
    val strb = UInt((CsrMap.dataBits / 8).W)
  }))
  val b = Decoupled(UInt(2.W))
  val ar = Flipped(Decoupled(UInt(addressBits.W)))
  val r = Decoupled(new Bundle {
    val data = UInt(CsrMap.dataBits.W)
    val resp = UInt(2.W)
  })
}

/** [[MonitoredArmAxiLite]]'s ports: the sample streams, the AXI4-Lite register slave, the interrupt. */
class MonitoredArmAxiLiteIO(p: ArmParams, map: CsrMap) extends ArmIO(p) {
  val csr = new AxiLiteSlave(map.addressBits + 2)
  val irq = Output(Bool())
}

/**
 * The same register map behind AXI4-Lite: byte addresses (`map`'s offsets), converted to word transfers on
 * [[MonitoredArmAvalon]]'s slave, so the decoder is the Avalon one. A write is taken when its address and
 * data are both valid (AXI4 lets a slave wait for both), one at a time: the next waits for the response's
 * handshake. A read is taken when no write is and no read is outstanding; its data stays valid until taken.
 * Responses are OKAY; `strb` is ignored (registers are written whole, as on Avalon).
 */
class MonitoredArmAxiLite(val p: ArmParams, val monitor: MonitorParams, val map: CsrMap)(implicit
    multiplierImpl: MultiplierImpl
) extends Module {
  override def desiredName = s"MonitoredArmAxiLite_${p.tag}"
  val io = IO(new MonitoredArmAxiLiteIO(p, map))

  private val inner = Module(new MonitoredArmAvalon(p, monitor, map))
  inner.io.in <> io.in
  io.out := inner.io.out
  io.irq := inner.io.irq
  private val avalon = inner.io.csr

  private val bValid = RegInit(false.B)
  private val writeTaken = io.csr.aw.valid && io.csr.w.valid && !bValid
  io.csr.aw.ready := writeTaken
  io.csr.w.ready := writeTaken
  when(writeTaken)(bValid := true.B).elsewhen(io.csr.b.ready)(bValid := false.B)
  io.csr.b.valid := bValid
  io.csr.b.bits := 0.U

  private val rValid = RegInit(false.B)
  private val rData = Reg(UInt(CsrMap.dataBits.W))
  private val pending = RegInit(false.B)
  private val readTaken = io.csr.ar.valid && !writeTaken && !pending && !rValid
  io.csr.ar.ready := readTaken
  when(readTaken)(pending := true.B)
  when(avalon.readdatavalid) {
    pending := false.B
    rValid := true.B
    rData := avalon.readdata
  }.elsewhen(io.csr.r.ready)(rValid := false.B)
  io.csr.r.valid := rValid
  io.csr.r.bits.data := rData
  io.csr.r.bits.resp := 0.U

  private def word(byteAddress: DecoupledIO[UInt]) = (byteAddress.bits >> 2).asUInt
  avalon.address := Mux(writeTaken, word(io.csr.aw), word(io.csr.ar))
  avalon.write := writeTaken
  avalon.writedata := io.csr.w.bits.data
  avalon.read := readTaken
}
