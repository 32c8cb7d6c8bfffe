package reducerload.monitor

import chisel3._
import chiseltest._

import scala.collection.mutable.ArrayBuffer

/** What the test does in one clock: the monitor's inputs and, optionally, a register-bank address. */
final case class DriveCycle(cycle: MonitorCycle, readAddress: Option[Int] = None)

/** Per clock, what came out: snapshotDone, and the word read for the previous cycle's address. */
final case class ObservedCycle(snapshotDone: Boolean, readData: Option[BigInt])

/** The only code that talks to the simulator for ReducerMonitor. */
object MonitorDriver {

  def poke(dut: ReducerMonitor, d: DriveCycle): Unit = {
    val p = dut.p
    d.cycle.sample match {
      case Some(s) =>
        dut.io.in.valid.poke(true.B)
        (0 until p.joints).foreach { j =>
          dut.io.in.bits.torque(j).poke(s.torque(j).S)
          dut.io.in.bits.velocity(j).poke(s.velocity(j).S)
          dut.io.in.bits.outOfRange(j).poke(s.outOfRange(j).B)
        }
      case None => dut.io.in.valid.poke(false.B)
    }
    dut.io.host.snapshot.poke(d.cycle.snapshot.B)
    dut.io.host.clear.poke(d.cycle.clear.B)
    dut.io.host.readAddress.poke(d.readAddress.getOrElse(0).U)
  }

  /** Drive every cycle; the read data of cycle k's address is reported with cycle k. */
  def run(dut: ReducerMonitor, drive: IndexedSeq[DriveCycle]): IndexedSeq[ObservedCycle] = {
    dut.clock.setTimeout(0)
    val done = ArrayBuffer.empty[Boolean]
    val data = ArrayBuffer.empty[BigInt]
    drive.foreach { d =>
      poke(dut, d)
      done += dut.io.host.snapshotDone.peek().litToBoolean
      dut.clock.step()
      data += dut.io.host.readData.peek().litValue
    }
    drive.indices.map(i => ObservedCycle(done(i), drive(i).readAddress.map(_ => data(i))))
  }
}
