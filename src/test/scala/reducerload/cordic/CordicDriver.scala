package reducerload.cordic

import chisel3._
import chiseltest._
import reducerload.sim.rtl.Cycle

/** The only place that talks to the simulator for CORDIC tests: drive a stimulus, record outputs. */
object CordicDriver {
  def run(dut: CordicSinCos, stimulus: IndexedSeq[Cycle[BigInt]]): IndexedSeq[Option[(BigInt, BigInt)]] = {
    dut.clock.setTimeout(0)
    stimulus.map { cycle =>
      cycle match {
        case Cycle.Reset     => dut.reset.poke(true.B); dut.io.in.valid.poke(false.B)
        case Cycle.Bubble    => dut.io.in.valid.poke(false.B)
        case Cycle.Sample(a) => dut.io.in.valid.poke(true.B); dut.io.in.bits.poke(a.U)
      }
      val out =
        if (dut.io.out.valid.peek().litToBoolean)
          Some((dut.io.out.bits.cos.peek().litValue, dut.io.out.bits.sin.peek().litValue))
        else None
      dut.clock.step()
      dut.reset.poke(false.B)
      out
    }
  }
}
