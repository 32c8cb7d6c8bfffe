package reducerload.regmap

import chisel3._
import chisel3.util.{Decoupled, DecoupledIO}

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

/**
 * An AXI4-Lite slave onto an Avalon-MM slave (the one decoder, [[ReducerLoadCore]]'s): byte addresses
 * converted to word transfers. A write is taken when its address and data are both valid (AXI4 lets a slave
 * wait for both), one at a time: the next waits for the response's handshake. A read is taken when no write
 * is and no read is outstanding; its data stays valid until taken. Responses are OKAY; `strb` is ignored
 * (registers are written whole, as on Avalon).
 */
class AxiLiteBridge(wordAddressBits: Int) extends Module {
  val io = IO(new Bundle {
    val axi = new AxiLiteSlave(wordAddressBits + 2)
    val avalon = Flipped(new AvalonSlave(wordAddressBits))
  })
  private val csr = io.axi
  private val avalon = io.avalon

  private val bValid = RegInit(false.B)
  private val writeTaken = csr.aw.valid && csr.w.valid && !bValid
  csr.aw.ready := writeTaken
  csr.w.ready := writeTaken
  when(writeTaken)(bValid := true.B).elsewhen(csr.b.ready)(bValid := false.B)
  csr.b.valid := bValid
  csr.b.bits := 0.U

  private val rValid = RegInit(false.B)
  private val rData = Reg(UInt(CsrMap.dataBits.W))
  private val pending = RegInit(false.B)
  private val readTaken = csr.ar.valid && !writeTaken && !pending && !rValid
  csr.ar.ready := readTaken
  when(readTaken)(pending := true.B)
  when(avalon.readdatavalid) {
    pending := false.B
    rValid := true.B
    rData := avalon.readdata
  }.elsewhen(csr.r.ready)(rValid := false.B)
  csr.r.valid := rValid
  csr.r.bits.data := rData
  csr.r.bits.resp := 0.U

  private def word(byteAddress: DecoupledIO[UInt]) = (byteAddress.bits >> 2).asUInt
  avalon.address := Mux(writeTaken, word(csr.aw), word(csr.ar))
  avalon.write := writeTaken
  avalon.writedata := csr.w.bits.data
  avalon.read := readTaken
}
