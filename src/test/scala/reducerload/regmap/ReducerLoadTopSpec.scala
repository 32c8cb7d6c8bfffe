package reducerload.regmap

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.arm.{ArmModel, ArmOutputCodes, ArmSample, PayloadedArm}
import reducerload.compiler.Compiled
import reducerload.dynamics.RandomChains
import reducerload.fixedpoint.Rounding
import reducerload.graph.SampleCodes
import reducerload.robot.{Mat3, RigidBody, Vec3}
import reducerload.testutil.{Seeds, SimBackend}
import reducerload.testutil.SimBackend.multiplierImpl

import scala.collection.mutable.ArrayBuffer
import scala.util.Random

/** The wrapper's sample streams as a test drives them, one clock at a time (the only simulator calls). */
trait StreamPins {
  def offer(valid: Boolean, beat: BigInt): Unit
  def inReady: Boolean
  def outReady(ready: Boolean): Unit
  def outValid: Boolean
  def outBeat: BigInt
}

/** A register slave as a host sees it: blocking word transfers; every clock they take goes through `step`. */
trait RegisterBus {
  def read(word: Int): BigInt
  def write(word: Int, data: BigInt): Unit
}

/**
 * Avalon-MM master transfers on a wrapper's `csr` slave: word addresses, one-clock writes, reads answered
 * with `readdatavalid`. `step` advances one clock (the test's streams keep running through it): reusable by
 * any test or bus-functional model that drives [[ReducerLoadAvalon]].
 */
final class AvalonMm(csr: AvalonSlave, step: () => Unit) extends RegisterBus {
  csr.read.poke(false.B); csr.write.poke(false.B)
  def write(word: Int, data: BigInt): Unit = {
    csr.address.poke(word.U); csr.writedata.poke(data.U); csr.write.poke(true.B)
    step()
    csr.write.poke(false.B)
  }
  def read(word: Int): BigInt = {
    csr.address.poke(word.U); csr.read.poke(true.B)
    step()
    csr.read.poke(false.B)
    var waited = 0
    while (!csr.readdatavalid.peek().litToBoolean) {
      require(waited < 8, s"read of word $word: no readdatavalid within 8 clocks"); step(); waited += 1
    }
    csr.readdata.peek().litValue
  }
}

/** AXI4-Lite master transfers on a wrapper's `csr` slave (byte addresses), as [[AvalonMm]]. */
final class AxiLiteMaster(csr: AxiLiteSlave, step: () => Unit) extends RegisterBus {
  Seq(csr.aw.valid, csr.w.valid, csr.ar.valid, csr.b.ready, csr.r.ready).foreach(_.poke(false.B))
  private def await(ready: Bool, what: String): Unit = {
    var waited = 0
    while (!ready.peek().litToBoolean) { require(waited < 8, s"$what: no handshake"); step(); waited += 1 }
  }
  def write(word: Int, data: BigInt): Unit = {
    csr.aw.bits.poke((4 * word).U); csr.aw.valid.poke(true.B)
    csr.w.bits.data.poke(data.U); csr.w.bits.strb.poke(0xf.U); csr.w.valid.poke(true.B)
    await(csr.aw.ready, s"write of word $word")
    step()
    csr.aw.valid.poke(false.B); csr.w.valid.poke(false.B)
    await(csr.b.valid, s"write response of word $word")
    assert(csr.b.bits.peek().litValue == 0, "write response not OKAY")
    csr.b.ready.poke(true.B); step(); csr.b.ready.poke(false.B)
  }
  def read(word: Int): BigInt = {
    csr.ar.bits.poke((4 * word).U); csr.ar.valid.poke(true.B)
    await(csr.ar.ready, s"read of word $word")
    step()
    csr.ar.valid.poke(false.B)
    await(csr.r.valid, s"read data of word $word")
    val data = csr.r.bits.data.peek().litValue
    csr.r.ready.poke(true.B); step(); csr.r.ready.poke(false.B)
    data
  }
}

/**
 * The wrapper scenario in plain Scala: seeded samples offered with random bubbles, the output under random
 * back-pressure with the protocol checked every clock (valid held until accepted, data stable while waiting);
 * payloads written and committed through the registers while samples stream; the identification block, a
 * staged read-back, the counters and one register-driven sample read through the bus. Every output is
 * compared in order with ArmModel for the payload committed when its sample was taken.
 */
final class WrapperScenario(c: Compiled, label: String) {
  private val p = c.arm
  private val map = ReducerLoadRegisters(c)
  private val model = new ArmModel(p)
  private val params = p.numerics.parameters
  private val port = p.numerics.parameterPortFormat
  private val seed = Seeds(s"ReducerLoadTopSpec $label", 32)
  private val rng = new Random(seed)
  private val inFields = StreamLayout.input(p)
  private val outFields = StreamLayout.output(p)
  private val joints = p.chain.size
  private val outputs = p.graph.outputs.size
  private def word(name: String) = map.register(name).word

  // The model of the registers and of the stream.
  private var staged = PayloadedArm.resetCodes(p)
  private var active = staged
  private var sequence = 0
  private val taken = ArrayBuffer.empty[(SampleCodes, Int)]
  private val received = ArrayBuffer.empty[(ArmOutputCodes, Int)]
  private var offered = Option.empty[SampleCodes]
  private var stalls = 0
  private var waiting = Option.empty[BigInt] // the output beat offered and not yet accepted
  private var streaming = true
  private var clocks = 0
  private var blocked = 0 // clocks left of a long back-pressure stretch (fills the output queue)
  private var longestWait = 0
  private var waited = 0

  private def beat(s: SampleCodes): BigInt =
    StreamLayout.pack(inFields, s.angles ++ s.velocities ++ s.accelerations)

  private def fresh(): SampleCodes = {
    val scale = if (rng.nextDouble() < 0.1) 1.3 else 0.95
    val (q, qd, qdd) =
      RandomChains.sample(rng, p.maxVelocity.map(_ * scale), p.maxAcceleration.map(_ * scale))
    model.encode(ArmSample(q, qd, qdd))
  }

  /** One clock of both streams, then the edge (`edge`). */
  def cycle(pins: StreamPins, edge: () => Unit): Unit = {
    if (offered.isEmpty && streaming && rng.nextDouble() < 0.6) offered = Some(fresh())
    pins.offer(offered.isDefined, offered.fold(BigInt(0))(beat))
    if (!streaming) blocked = 0 // drain: the output takes again
    else if (blocked == 0 && rng.nextDouble() < 0.0005) blocked = 1000 + rng.nextInt(2000)
    val ready = blocked == 0 && rng.nextDouble() < 0.7
    blocked = (blocked - 1).max(0)
    pins.outReady(ready)
    val valid = pins.outValid
    waiting.foreach { w =>
      assert(valid, s"[$label] clock $clocks: out valid dropped before the beat was accepted")
      assert(pins.outBeat == w, s"[$label] clock $clocks: out data changed while waiting")
    }
    if (valid) {
      val b = pins.outBeat
      if (ready) {
        val v = StreamLayout.unpack(outFields, b)
        val seq = if (params.nonEmpty) v.last.toInt else 0
        received += ((
          ArmOutputCodes(v.take(joints).toIndexedSeq, v.slice(joints, 2 * joints).map(_ == 1).toIndexedSeq),
          seq
        ))
        waiting = None
        waited = 0
      } else {
        waiting = Some(b); waited += 1; longestWait = longestWait.max(waited)
      }
    }
    offered.foreach { s =>
      if (pins.inReady) {
        taken += ((s.copy(parameters = params.zip(active).toMap), sequence))
        offered = None
      } else stalls += 1
    }
    edge()
    clocks += 1
  }

  private def twos(code: BigInt, bits: Int) = code & ((BigInt(1) << bits) - 1)
  private def signed(code: BigInt, bits: Int) =
    if (code.testBit(bits - 1)) code - (BigInt(1) << bits) else code

  /** Writes that the model follows: the payload registers, the commit. */
  private def write(bus: RegisterBus, name: String, data: BigInt): Unit = {
    bus.write(word(name), data)
    map.register(name).register.source match {
      case Source.Parameter(k, 0) => staged = staged.updated(k, signed(data, 32))
      case Source.PayloadCommit =>
        active = staged.map(v => signed(twos(v, port.width), port.width))
        sequence = (sequence + 1) % (1 << PayloadedArm.sequenceBits)
      case _ => ()
    }
  }

  private def randomPayload(): Seq[BigInt] = {
    val spec = p.payload.get
    val m = rng.nextDouble() * spec.maxMass
    def coord() = (rng.nextDouble() * 2 - 1) * spec.comRadius / math.sqrt(3)
    val top = m * spec.maxGyrationRadius * spec.maxGyrationRadius
    val body = RigidBody(
      m,
      Vec3(coord(), coord(), coord()),
      Mat3.diagonal(Vec3(rng.nextDouble(), rng.nextDouble(), rng.nextDouble()) * (top * 0.5))
    )
    val values = spec.values(p.chain, body)
    params.map(s =>
      values.get(s).fold(active(params.indexOf(s)))(v => port.fromDouble(v, Rounding.HalfUp)._1)
    )
  }

  /** The whole scenario on one design: `bus` the register slave, `step` one clock of everything. */
  def run(bus: RegisterBus, step: () => Unit, irq: => Boolean): Unit = {
    val perSample = p.schedule.clocksPerSample
    // Identification, with samples streaming.
    AvalonCsrExpect.id(map).foreach { case (r, want) =>
      assert(bus.read(r.word) == want, s"[$label] ${r.cName}")
    }
    AvalonCsrExpect.independent(joints).foreach { case (name, want) =>
      val got = bus.read(word(name))
      assert((if (name == "id_shape") got & 0xff else got) == want, s"[$label] $name: ${got.toString(16)}")
    }
    // Payload commits while streaming.
    val commits = if (params.isEmpty) 0 else 3
    (0 until commits).foreach { i =>
      val codes = randomPayload()
      codes.zipWithIndex.foreach { case (v, k) =>
        write(bus, map.registers.find(_.register.source == Source.Parameter(k, 0)).get.cName, twos(v, 32))
      }
      val back = bus.read(map.registers.find(_.register.source == Source.Parameter(0, 0)).get.word)
      assert(
        signed(back, 32) == codes.head,
        s"[$label] staged mass read back ${signed(back, 32)}, wrote ${codes.head}"
      )
      (0 until 20 * perSample).foreach(_ => step())
      write(bus, "payload_commit", 1)
      assert(bus.read(word("payload_sequence")) == sequence, s"[$label] commit $i: sequence")
      (0 until 20 * perSample).foreach(_ => step())
    }
    if (commits == 0) (0 until 40 * perSample).foreach(_ => step())
    // The register-driven sample mode, once, while the stream runs.
    val s = fresh()
    Seq("q" -> s.angles, "qd" -> s.velocities, "qdd" -> s.accelerations).foreach { case (k, v) =>
      v.zipWithIndex.foreach { case (x, j) => bus.write(word(s"sample_${k}_j${j + 1}"), twos(x, 32)) }
    }
    val expectSequence = sequence
    val want = model.evaluate(s.copy(parameters = params.zip(active).toMap))
    bus.write(word("sample_start"), 1)
    var polls = 0
    while ((bus.read(word("sample_status")) & 2) == 0) {
      polls += 1; require(polls < 10 * p.latency, "sample mode never done")
    }
    val tauWords = ReducerLoadRegisters.wordsOf(p.analysis.outputPortFormat.width)
    val tau = (0 until joints).map { j =>
      val ws = (0 until tauWords).map(w =>
        bus.read(word(if (tauWords == 1) s"sample_tau_j${j + 1}" else s"sample_tau_j${j + 1}_w$w"))
      )
      signed(ws.zipWithIndex.map { case (v, w) => v << (32 * w) }.sum, 32 * tauWords)
    }
    val flags = bus.read(word("sample_flags"))
    assert(tau == want.tau, s"[$label] register-driven sample: tau $tau, model ${want.tau}")
    assert((0 until joints).map(flags.testBit) == want.outOfRange, s"[$label] register-driven sample flags")
    if (params.nonEmpty) assert(bus.read(word("sample_sequence")) == expectSequence)
    // Drain: stop offering, let every sample out, then the counters.
    streaming = false
    (0 until p.latency + 4 * perSample + 64).foreach(_ => step())
    assert(received.size == taken.size, s"[$label] ${taken.size} samples taken, ${received.size} given")
    val wrong = taken.zip(received).zipWithIndex.collect {
      case (((codes, seq), (out, outSeq)), i) if model.evaluate(codes) != out || seq != outSeq =>
        s"sample $i: RTL $out seq $outSeq, model ${model.evaluate(codes)} seq $seq"
    }
    assert(wrong.isEmpty, s"[$label] ${wrong.size} outputs differ: ${wrong.take(3).mkString("; ")}")
    val stallsBefore = stalls
    assert(bus.read(word("counters_samples_in")) == taken.size, s"[$label] samples_in")
    assert(bus.read(word("counters_samples_out")) == received.size, s"[$label] samples_out")
    val oor = received.count(_._1.outOfRange.exists(identity))
    assert(bus.read(word("counters_out_of_range")) == oor, s"[$label] out_of_range")
    assert(bus.read(word("counters_stalls")) == stallsBefore, s"[$label] stalls")
    assert(c.monitor.isDefined || !irq, s"[$label] the interrupt line without the monitor")
    println(
      s"[wrapper $label] ${p.chain.name} II=$perSample latency ${p.latency}: ${taken.size} samples in order, " +
        s"bit-exact with the model ($oor out of range, $stalls stalled clocks, ${taken.map(_._2).distinct.size} payload sequences), " +
        s"register-driven sample ok, $clocks clocks, longest output wait $longestWait clocks"
    )
    // A wait longer than the samples the queue holds at one per II: the full output stalled the input.
    assert(longestWait > (p.latency / perSample + 3) * perSample, s"[$label] the output queue never filled")
    assert(taken.map(_._2).distinct.size == commits + 1, s"[$label] payload sequences seen")
  }
}

/**
 * The `reducer_load` wrapper (Verilator with REDUCERLOAD_SIM=verilator): the UR5 with a run-time payload and
 * gravity at its shared block-RAM schedule, wrapped for Avalon and for AXI, one simulation each, every check
 * of [[WrapperScenario]] in it.
 */
class ReducerLoadTopSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "the reducer_load wrapper"

  private lazy val ur5 = ReducerLoadTopDesigns.ur5Payloaded

  it should "stream the UR5 with payload commits through Avalon-ST and Avalon-MM, bit-exact, in order, none lost" in {
    val c = ur5
    val map = ReducerLoadRegisters(c)
    val scenario = new WrapperScenario(c, "avalon")
    test(new ReducerLoadAvalon(c.arm, c.monitor, map, "reducer_load"))
      .withAnnotations(SimBackend.annotations) { dut =>
        dut.clock.setTimeout(0)
        val pins = new StreamPins {
          def offer(valid: Boolean, beat: BigInt): Unit = {
            dut.in.valid.poke(valid.B); dut.in.data.poke(beat.U)
          }
          def inReady: Boolean = dut.in.ready.peek().litToBoolean
          def outReady(ready: Boolean): Unit = dut.out.ready.poke(ready.B)
          def outValid: Boolean = dut.out.valid.peek().litToBoolean
          def outBeat: BigInt = dut.out.data.peek().litValue
        }
        val step = () => scenario.cycle(pins, () => dut.clock.step())
        scenario.run(new AvalonMm(dut.csr, step), step, dut.irq.irq.peek().litToBoolean)
        // Then the C driver through the bus-functional model on the same design (no second Verilator
        // build): identification, a payload written from SI units, committed and read back, one sample in
        // the register-driven sample mode; from reset, so the gravity is the elaboration one.
        assume(CProgram.available, "gcc is needed for the C driver")
        dut.in.valid.poke(false.B); dut.out.ready.poke(true.B)
        dut.reset.poke(true.B); dut.clock.step(); dut.reset.poke(false.B)
        val bus = new AvalonMm(dut.csr, () => dut.clock.step())
        val seed = Seeds("ReducerLoadTopSpec C driver", 32)
        val exe =
          CDriver.buildTestProgram(reducerload.testutil.Scratch.dir("c-driver-ur5-"), c, "ReducerLoadTopSpec")
        val run = CDriverScenario.run(c, exe, bus.read, bus.write, seed)
        info(
          s"C driver on the UR5 wrapper (seed $seed): ${run.reads} reads, ${run.writes} writes, payload round trip and sample mode as the models say"
        )
      }
  }

  it should "stream the UR5 through AXI4-Stream and AXI4-Lite the same way" in {
    val c = ur5
    val map = ReducerLoadRegisters(c)
    val scenario = new WrapperScenario(c, "axi")
    test(new ReducerLoadAxi(c.arm, c.monitor, map, "reducer_load")).withAnnotations(SimBackend.annotations) {
      dut =>
        dut.clock.setTimeout(0)
        val pins = new StreamPins {
          def offer(valid: Boolean, beat: BigInt): Unit = {
            dut.in.tvalid.poke(valid.B); dut.in.tdata.poke(beat.U)
          }
          def inReady: Boolean = dut.in.tready.peek().litToBoolean
          def outReady(ready: Boolean): Unit = dut.out.tready.poke(ready.B)
          def outValid: Boolean = dut.out.tvalid.peek().litToBoolean
          def outBeat: BigInt = dut.out.tdata.peek().litValue
        }
        val step = () => scenario.cycle(pins, () => dut.clock.step())
        scenario.run(new AxiLiteMaster(dut.csr, step), step, dut.irq.irq.peek().litToBoolean)
    }
  }
}
