package reducerload.regmap

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.arm.{ArmModel, ArmSample}
import reducerload.dynamics.RandomChains
import reducerload.graph.SampleCodes
import reducerload.monitor.{JointField, MonitorCycle, MonitorModel, RegisterKey, TrajectorySummary}
import reducerload.testutil.{Seeds, SimBackend}
import reducerload.testutil.SimBackend.multiplierImpl

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Paths}
import scala.collection.mutable.ArrayBuffer
import scala.util.Random

/** What the test expects, in plain Scala from the description, the models and independent constants. */
object AvalonCsrExpect {

  /**
   * Every identification register's value, from the description (its constants are what the RTL must hold).
   */
  def id(map: CsrMap): Seq[(PlacedRegister, BigInt)] =
    map.block("id").registers.map(r => r -> r.register.reset)

  /** Identification values the test knows on its own: the magic ("RLOD"), build.sbt's version, the joints. */
  def independent(joints: Int): Map[String, BigInt] = {
    val build = new String(
      Files.readAllBytes(Paths.get(sys.env.getOrElse("REDUCERLOAD_CWD", ".")).resolve("build.sbt")),
      StandardCharsets.UTF_8
    )
    val v = """ThisBuild / version := "(\d+)\.(\d+)\.(\d+)""".r.findFirstMatchIn(build).get
    val Seq(major, minor, patch) = (1 to 3).map(i => v.group(i).toInt)
    Map(
      "id_magic" -> BigInt("524C4F44", 16),
      "id_version" -> BigInt((major << 16) | (minor << 8) | patch),
      "id_shape" -> BigInt(joints)
    )
  }

  /** The monitor's shadow bank after `codes` and one snapshot (no clear): MonitorModel fed by ArmModel. */
  def monitorBank(c: reducerload.compiler.Compiled, codes: Seq[SampleCodes]): IndexedSeq[BigInt] = {
    val m = c.monitor.get
    val fed = TrajectorySummary.monitorInputs(c.arm, codes)
    val model = new MonitorModel(m)
    val state =
      model.run(fed.iterator.map(s => MonitorCycle(Some(s))) ++ Iterator(MonitorCycle(None, snapshot = true)))
    state.shadow.bank(m)
  }

  /** Whether a joint is in a momentary-peak event at the snapshot (the live flag, unchanged since). */
  def inEvent(c: reducerload.compiler.Compiled, bank: IndexedSeq[BigInt]): Boolean = {
    val m = c.monitor.get
    val values = m.registerMap.decode(bank)
    (0 until m.joints).exists(j =>
      values(RegisterKey.Joint(j, JointField.Flags)).testBit(JointField.FlagBit.inEvent)
    )
  }

  /** The interrupt status after `bank`'s samples from a cleared monitor: a flag seen on any joint. */
  def events(c: reducerload.compiler.Compiled, bank: IndexedSeq[BigInt]): BigInt = {
    val m = c.monitor.get
    val values = m.registerMap.decode(bank)
    ReducerLoadRegisters.Event.all.map { e =>
      val seen = (0 until m.joints).exists(j =>
        values(RegisterKey.Joint(j, JointField.Flags)).testBit(ReducerLoadRegisters.Event.flagBit(e))
      )
      if (seen) BigInt(1) << e.bit else BigInt(0)
    }.sum
  }
}

/** The only code that talks to the simulator for [[MonitoredArmAvalon]]. */
object AvalonDriver {
  def idle(dut: MonitoredArmAvalon): Unit = {
    dut.io.csr.read.poke(false.B)
    dut.io.csr.write.poke(false.B)
    dut.io.in.valid.poke(false.B)
  }

  def write(dut: MonitoredArmAvalon, word: Int, data: BigInt): Unit = {
    dut.io.csr.address.poke(word.U)
    dut.io.csr.writedata.poke(data.U)
    dut.io.csr.write.poke(true.B)
    dut.clock.step()
    dut.io.csr.write.poke(false.B)
  }

  /** One read; the data in the cycle readdatavalid is high. */
  def read(dut: MonitoredArmAvalon, word: Int): BigInt = {
    dut.io.csr.address.poke(word.U)
    dut.io.csr.read.poke(true.B)
    dut.clock.step()
    dut.io.csr.read.poke(false.B)
    var waited = 0
    while (!dut.io.csr.readdatavalid.peek().litToBoolean) {
      require(waited < 8, s"no readdatavalid 8 clocks after a read of word $word")
      dut.clock.step(); waited += 1
    }
    dut.io.csr.readdata.peek().litValue
  }

  /** Offer each sample until taken; returns the clocks a sample waited (valid and not ready). */
  def stream(dut: MonitoredArmAvalon, codes: Seq[SampleCodes]): Int = {
    var stalls = 0
    codes.foreach { s =>
      dut.io.in.valid.poke(true.B)
      s.angles.indices.foreach { j =>
        dut.io.in.bits.q(j).poke(s.angles(j).U)
        dut.io.in.bits.qd(j).poke(s.velocities(j).S)
        dut.io.in.bits.qdd(j).poke(s.accelerations(j).S)
      }
      while (!dut.io.in.ready.peek().litToBoolean) { stalls += 1; dut.clock.step() }
      dut.clock.step()
    }
    dut.io.in.valid.poke(false.B)
    stalls
  }
}

/**
 * The monitored planar arm behind its Avalon-MM register slave, on one compiled design: the identification
 * block read through the bus equals the description's constants and the independently known ones; after a
 * seeded stream (some samples beyond the declared ranges) a snapshot written through the bus gives, word for
 * word, the bank of MonitorModel fed by ArmModel; the counters, the interrupt status, mask, line and W1C.
 */
class AvalonCsrSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "MonitoredArmAvalon"

  it should "read the identification block and a snapshot of the monitor through the bus as the models say" in {
    val c = RegMapDesign.compiled
    val map = RegMapDesign.map
    val m = c.monitor.get
    val seed = Seeds("AvalonCsrSpec", 32)
    val rng = new Random(seed)
    val model = new ArmModel(c.arm)
    val samples = IndexedSeq.tabulate(SimBackend.scale(300)) { i =>
      val scale = if (i % 25 == 7) 1.4 else 0.95
      val (q, qd, qdd) =
        RandomChains.sample(rng, c.arm.maxVelocity.map(_ * scale), c.arm.maxAcceleration.map(_ * scale))
      ArmSample(q, qd, qdd)
    }
    val codes = samples.map(model.encode)
    val outOfRange = codes.count(s => model.evaluate(s).outOfRange.exists(identity))
    val bank = AvalonCsrExpect.monitorBank(c, codes)
    val events = AvalonCsrExpect.events(c, bank)
    println(
      s"[avalon-csr] ${codes.size} samples ($outOfRange out of range), expected interrupt status $events"
    )
    def word(name: String) = map.register(name).word
    val monitor = map.block("monitor")

    test(new MonitoredArmAvalon(c.arm, m, map)).withAnnotations(SimBackend.annotations) { dut =>
      dut.clock.setTimeout(0)
      AvalonDriver.idle(dut)
      dut.clock.step()
      AvalonCsrExpect.id(map).foreach { case (r, want) =>
        assert(AvalonDriver.read(dut, r.word) == want, s"${r.cName}")
      }
      AvalonCsrExpect.independent(m.joints).foreach { case (name, want) =>
        val got = AvalonDriver.read(dut, word(name))
        assert((if (name == "id_shape") got & 0xff else got) == want, s"$name: ${got.toString(16)}")
      }
      AvalonDriver.write(dut, word("irq_mask"), (BigInt(1) << ReducerLoadRegisters.Event.all.size) - 1)
      val stalls = AvalonDriver.stream(dut, codes)
      dut.clock.step(c.arm.latency + 2)
      AvalonDriver.write(dut, word("ctrl_control"), BigInt(1) << ReducerLoadRegisters.Command.Snapshot.bit)
      val inEvent = if (AvalonCsrExpect.inEvent(c, bank)) BigInt(2) else BigInt(0)
      assert(AvalonDriver.read(dut, word("ctrl_status")) == inEvent, "snapshot_ready right after the request")
      dut.clock.step(m.snapshotLatency + 1)
      assert(
        AvalonDriver.read(dut, word("ctrl_status")) == (inEvent | 1),
        "snapshot_ready after the snapshot latency"
      )
      val read = ArrayBuffer.empty[BigInt]
      monitor.registers.foreach(r => read += AvalonDriver.read(dut, r.word))
      val monitorWords = m.registerMap.entries.flatMap(e => (0 until e.words).map(w => e.address + w))
      val want = monitorWords.map(bank)
      val wrong = monitor.registers.indices
        .filter(i => read(i) != want(i))
        .map(i => s"${monitor.registers(i).cName}: bus ${read(i)}, model ${want(i)}")
      assert(wrong.isEmpty, wrong.mkString("; "))
      assert(AvalonDriver.read(dut, word("counters_samples_in")) == codes.size)
      assert(AvalonDriver.read(dut, word("counters_samples_out")) == codes.size)
      assert(AvalonDriver.read(dut, word("counters_out_of_range")) == outOfRange)
      assert(AvalonDriver.read(dut, word("counters_stalls")) == stalls)
      assert(AvalonDriver.read(dut, word("irq_status")) == events)
      assert(dut.io.irq.peek().litToBoolean == (events != 0))
      AvalonDriver.write(dut, word("irq_status"), events)
      assert(AvalonDriver.read(dut, word("irq_status")) == 0, "W1C left bits set")
      assert(!dut.io.irq.peek().litToBoolean)
      AvalonDriver.write(
        dut,
        word("ctrl_control"),
        BigInt(1) << ReducerLoadRegisters.Command.ClearCounters.bit
      )
      dut.clock.step()
      assert(AvalonDriver.read(dut, word("counters_samples_in")) == 0)
      assert(AvalonDriver.read(dut, map.block("payload").base) == 0, "the reserved payload block reads 0")
    }
  }
}
