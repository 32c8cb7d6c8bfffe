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
   * `n` seeded samples, sample i within `scale(i)` times the declared ranges (beyond 1: clamped, flagged).
   */
  def samples(c: reducerload.compiler.Compiled, rng: Random, n: Int)(
      scale: Int => Double
  ): IndexedSeq[ArmSample] =
    IndexedSeq.tabulate(n) { i =>
      val (q, qd, qdd) =
        RandomChains.sample(rng, c.arm.maxVelocity.map(_ * scale(i)), c.arm.maxAcceleration.map(_ * scale(i)))
      ArmSample(q, qd, qdd)
    }

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

/** A register bus and sample stream as the test drives them (the only code that talks to the simulator). */
trait CsrBus {
  def read(word: Int): BigInt
  def write(word: Int, data: BigInt): Unit

  /** Offer each sample until taken; returns the clocks a sample waited (valid and not ready). */
  def stream(codes: Seq[SampleCodes]): Int
  def irq: Boolean
  def step(n: Int): Unit
}

object CsrBus {

  /** Offer each sample as one beat ([[StreamLayout.input]]) until taken; the output always ready. */
  private def stream(
      clock: Clock,
      p: reducerload.arm.ArmParams,
      valid: Bool,
      data: UInt,
      ready: Bool,
      codes: Seq[SampleCodes]
  ): Int = {
    var stalls = 0
    codes.foreach { s =>
      valid.poke(true.B)
      data.poke(StreamLayout.pack(StreamLayout.input(p), s.angles ++ s.velocities ++ s.accelerations).U)
      while (!ready.peek().litToBoolean) { stalls += 1; clock.step() }
      clock.step()
    }
    valid.poke(false.B)
    stalls
  }

  def avalon(dut: ReducerLoadAvalon): CsrBus = new CsrBus {
    dut.in.valid.poke(false.B); dut.out.ready.poke(true.B)
    private val mm = new AvalonMm(dut.csr, () => dut.clock.step())
    def write(word: Int, data: BigInt): Unit = mm.write(word, data)
    def read(word: Int): BigInt = mm.read(word)
    def stream(codes: Seq[SampleCodes]): Int =
      CsrBus.stream(dut.clock, dut.p, dut.in.valid, dut.in.data, dut.in.ready, codes)
    def irq: Boolean = dut.irq.irq.peek().litToBoolean
    def step(n: Int): Unit = dut.clock.step(n)
  }

  def axiLite(dut: ReducerLoadAxi): CsrBus = new CsrBus {
    dut.in.tvalid.poke(false.B); dut.out.tready.poke(true.B)
    private val lite = new AxiLiteMaster(dut.csr, () => dut.clock.step())
    def write(word: Int, data: BigInt): Unit = lite.write(word, data)
    def read(word: Int): BigInt = lite.read(word)
    def stream(codes: Seq[SampleCodes]): Int =
      CsrBus.stream(dut.clock, dut.p, dut.in.tvalid, dut.in.tdata, dut.in.tready, codes)
    def irq: Boolean = dut.irq.irq.peek().litToBoolean
    def step(n: Int): Unit = dut.clock.step(n)
  }
}

/**
 * The monitored planar arm behind its Avalon-MM register slave, and behind AXI4-Lite (one compiled design
 * each): the identification block read through the bus equals the description's constants and the
 * independently known ones; after a seeded stream (some samples beyond the declared ranges) a snapshot
 * written through the bus gives, word for word, the bank of MonitorModel fed by ArmModel; the counters, the
 * interrupt status, mask, line and W1C.
 */
class AvalonCsrSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "the reducer_load wrapper's registers (monitored planar3)"

  /** The test on any bus: the expected values computed here, the bus driven by the returned check. */
  private def scenario(label: String): CsrBus => Unit = {
    val c = RegMapDesign.compiled
    val map = RegMapDesign.map
    val m = c.monitor.get
    val seed = Seeds(s"AvalonCsrSpec $label", 32)
    val rng = new Random(seed)
    val model = new ArmModel(c.arm)
    val samples = AvalonCsrExpect.samples(c, rng, SimBackend.scale(300))(i => if (i % 25 == 7) 1.4 else 0.95)
    val codes = samples.map(model.encode)
    val outOfRange = codes.count(s => model.evaluate(s).outOfRange.exists(identity))
    val bank = AvalonCsrExpect.monitorBank(c, codes)
    val events = AvalonCsrExpect.events(c, bank)
    println(
      s"[csr $label] ${codes.size} samples ($outOfRange out of range), expected interrupt status $events"
    )
    def word(name: String) = map.register(name).word
    val monitor = map.block("monitor")

    def check(bus: CsrBus): Unit = {
      bus.step(1)
      AvalonCsrExpect.id(map).foreach { case (r, want) =>
        assert(bus.read(r.word) == want, s"${r.cName}")
      }
      AvalonCsrExpect.independent(m.joints).foreach { case (name, want) =>
        val got = bus.read(word(name))
        assert((if (name == "id_shape") got & 0xff else got) == want, s"$name: ${got.toString(16)}")
      }
      bus.write(word("irq_mask"), (BigInt(1) << ReducerLoadRegisters.Event.all.size) - 1)
      val stalls = bus.stream(codes)
      bus.step(c.arm.latency + 2)
      bus.write(word("ctrl_control"), BigInt(1) << ReducerLoadRegisters.Command.Snapshot.bit)
      val inEvent = if (AvalonCsrExpect.inEvent(c, bank)) BigInt(2) else BigInt(0)
      assert(bus.read(word("ctrl_status")) == inEvent, "snapshot_ready right after the request")
      bus.step(m.snapshotLatency + 1)
      assert(
        bus.read(word("ctrl_status")) == (inEvent | 1),
        "snapshot_ready after the snapshot latency"
      )
      val read = ArrayBuffer.empty[BigInt]
      monitor.registers.foreach(r => read += bus.read(r.word))
      val monitorWords = m.registerMap.entries.flatMap(e => (0 until e.words).map(w => e.address + w))
      val want = monitorWords.map(bank)
      val wrong = monitor.registers.indices
        .filter(i => read(i) != want(i))
        .map(i => s"${monitor.registers(i).cName}: bus ${read(i)}, model ${want(i)}")
      assert(wrong.isEmpty, wrong.mkString("; "))
      assert(bus.read(word("counters_samples_in")) == codes.size)
      assert(bus.read(word("counters_samples_out")) == codes.size)
      assert(bus.read(word("counters_out_of_range")) == outOfRange)
      assert(bus.read(word("counters_stalls")) == stalls)
      assert(bus.read(word("irq_status")) == events)
      assert(bus.irq == (events != 0))
      bus.write(word("irq_status"), events)
      assert(bus.read(word("irq_status")) == 0, "W1C left bits set")
      assert(!bus.irq)
      bus.write(
        word("ctrl_control"),
        BigInt(1) << ReducerLoadRegisters.Command.ClearCounters.bit
      )
      bus.step(1)
      assert(bus.read(word("counters_samples_in")) == 0)
      assert(bus.read(map.block("payload").base) == 0, "the reserved payload block reads 0")
    }
    check
  }

  it should "read the identification block and a snapshot of the monitor through Avalon-MM as the models say" in {
    val c = RegMapDesign.compiled
    val check = scenario("avalon")
    test(new ReducerLoadAvalon(c.arm, c.monitor, RegMapDesign.map, "reducer_load"))
      .withAnnotations(SimBackend.annotations) { dut =>
        dut.clock.setTimeout(0)
        check(CsrBus.avalon(dut))
      }
  }

  it should "read and write the same registers through AXI4-Lite (byte addresses, handshakes, responses)" in {
    val c = RegMapDesign.compiled
    val check = scenario("axi4-lite")
    test(new ReducerLoadAxi(c.arm, c.monitor, RegMapDesign.map, "reducer_load"))
      .withAnnotations(SimBackend.annotations) { dut =>
        dut.clock.setTimeout(0)
        check(CsrBus.axiLite(dut))
      }
  }
}
