package reducerload.regmap

import chisel3._
import chisel3.util._
import reducerload.arm.{ArmDatapath, ArmInput, ArmOutput, ArmParams, JointSample, PayloadedArm}
import reducerload.monitor.{JointField, MonitorHostPort, MonitorParams, MonitoredArm}
import reducerload.pipeline.MultiplierImpl

/** One output sample of the core: torques and flags, and the payload sequence with run-time parameters. */
class CoreOutput(p: ArmParams) extends Bundle {
  val torques = new ArmOutput(p)
  val sequence = Option.when(p.numerics.parameters.nonEmpty)(UInt(PayloadedArm.sequenceBits.W))
}

/** [[ReducerLoadCore]]'s ports: sample streams (both ready/valid), the register slave, the interrupt. */
class ReducerLoadCoreIO(p: ArmParams, map: CsrMap) extends Bundle {
  val in = Flipped(Decoupled(new JointSample(p)))
  val out = Decoupled(new CoreOutput(p))
  val csr = new AvalonSlave(map.addressBits)

  /** High while (irq.status & irq.mask) != 0; low without the monitor. */
  val irq = Output(Bool())
}

/**
 * The bus-independent core of the `reducer_load` wrapper: the datapath (with the monitor when `monitor` is
 * given), the run-time payload and gravity registers, the register-driven sample mode, counters and the
 * interrupt, behind the register map `map` ([[ReducerLoadRegisters]]), whose decoder is generated here from
 * the layout and each register's [[Source]]; nothing here restates an address.
 *
 * The datapath's output is a Valid pipe; the core's output honours back-pressure through a queue, and a
 * sample is admitted only while the queue has room for it and for every sample in flight, so a full output
 * stalls the input and no sample is dropped, duplicated or reordered. A register-driven sample goes in ahead
 * of the stream's next one and its result lands in the sample block, not on the output.
 *
 * Payload: the datapath takes a sample's parameters with its joint state, so a commit between two samples is
 * at a sample boundary by construction (as [[PayloadedArm]]); the committed sequence number follows each
 * sample through a queue as deep as the samples in flight. Control pulses reach the monitor one clock after
 * the write; the monitor block's words pass straight to the monitor's read port. Counters wrap modulo 2^32.
 * An interrupt event is the rise of a live monitor flag on any joint; a W1C write and an event in the same
 * clock: the event wins.
 */
class ReducerLoadCore(val p: ArmParams, val monitor: Option[MonitorParams], val map: CsrMap)(implicit
    multiplierImpl: MultiplierImpl
) extends Module {
  import ReducerLoadRegisters.{Command, Event}
  override def desiredName = s"ReducerLoadCore_${p.tag}"
  val io = IO(new ReducerLoadCoreIO(p, map))
  private val joints = p.chain.size
  private val numerics = p.numerics
  private val parameters = numerics.parameters.size
  private val dataBits = CsrMap.dataBits

  // ---- the arm: the datapath, or the monitored arm ----
  private val (armIn, armOut, host, liveFlags) = monitor match {
    case Some(m) =>
      val a = Module(new MonitoredArm(p, m, liveFlags = true))
      (a.io.in, a.io.out, Some(a.io.host), a.io.flags)
    case None =>
      val a = Module(new ArmDatapath(p))
      (a.io.in, a.io.out, Option.empty[MonitorHostPort], Option.empty[Vec[UInt]])
  }

  private def only(source: Source): PlacedRegister = map.registers.filter(_.register.source == source) match {
    case Seq(r) => r
    case rs =>
      throw new IllegalArgumentException(s"register map ${map.name}: ${rs.size} registers of $source")
  }
  private def at(r: PlacedRegister): Bool = io.csr.address === r.word.U
  private def writing(source: Source): Bool =
    map.registers.filter(_.register.source == source).map(at).foldLeft(false.B)(_ || _) && io.csr.write
  private val data = io.csr.writedata

  /** A code kept as whole 32-bit words (sign-extended), so each register word is a slice. */
  private def words(width: Int): Int = ReducerLoadRegisters.wordsOf(width)
  private def slice(x: UInt, w: Int): UInt = x(dataBits * w + dataBits - 1, dataBits * w)
  private def written(x: UInt, w: Int): UInt = {
    val n = x.getWidth / dataBits
    VecInit((0 until n).map(i => if (i == w) data else slice(x, i))).asUInt
  }

  // ---- payload and gravity registers: staged (host-written), active (what samples take), sequence ----
  private val port = numerics.parameterPortFormat
  private val staged = Option.when(parameters > 0)(
    RegInit(
      VecInit(
        PayloadedArm
          .resetCodes(p)
          .map(c =>
            (c & ((BigInt(1) << (dataBits * words(port.width))) - 1)).U((dataBits * words(port.width)).W)
          )
      )
    )
  )
  private val active = Option.when(parameters > 0)(
    RegInit(VecInit(PayloadedArm.resetCodes(p).map(_.S(port.width.W))))
  )
  private val sequence = RegInit(0.U(PayloadedArm.sequenceBits.W))
  private val commit = writing(Source.PayloadCommit) && data(0)
  staged.foreach { s =>
    (0 until parameters).foreach { k =>
      (0 until words(port.width)).foreach { w =>
        when(io.csr.write && at(only(Source.Parameter(k, w))))(s(k) := written(s(k), w))
      }
    }
    // The staged values before this cycle's write: a write and a commit in one cycle commit the older one.
    when(commit) {
      active.get.zip(s).foreach { case (a, v) => a := v(port.width - 1, 0).asSInt }
      sequence := sequence +% 1.U
    }
  }

  // ---- the register-driven sample: inputs, start, busy/done, result ----
  private def inputWidth(kind: SampleKind): Int = kind match {
    case SampleKind.Angle        => numerics.angleBits
    case SampleKind.Velocity     => numerics.velocityPortFormat.width
    case SampleKind.Acceleration => numerics.accelerationPortFormat.width
  }
  private val sampleInputs: Map[SampleKind, Vec[UInt]] = SampleKind.all.map { k =>
    val r = RegInit(VecInit(Seq.fill(joints)(0.U((dataBits * words(inputWidth(k))).W))))
    (0 until joints).foreach { j =>
      (0 until words(inputWidth(k))).foreach { w =>
        when(io.csr.write && at(only(Source.SampleInput(k, j, w))))(r(j) := written(r(j), w))
      }
    }
    k -> r
  }.toMap
  private val busy = RegInit(false.B)
  private val done = RegInit(false.B)
  private val issued = RegInit(false.B) // the busy sample has entered the datapath
  private val start = writing(Source.SampleStart) && data(0) && !busy
  private val tauWords = words(p.analysis.outputPortFormat.width)
  private val resultTau = Reg(Vec(joints, UInt((dataBits * tauWords).W)))
  private val resultFlags = RegInit(0.U(joints.W))
  private val resultSequence = RegInit(0.U(PayloadedArm.sequenceBits.W))

  // ---- admission: the output queue has room for every sample in flight ----
  private val inFlight = p.latency / p.schedule.clocksPerSample + 2
  private val depth = inFlight + 1
  private val outQueue = Module(
    new Queue(new CoreOutput(p), depth, useSyncReadMem = depth > ReducerLoadCore.registerQueueMax)
  )
  private val pending = RegInit(0.U(log2Ceil(depth + 1).W))
  private val room = pending +& outQueue.io.count < depth.U
  private val fromRegisters = busy && !issued
  armIn.valid := (fromRegisters || io.in.valid) && room
  io.in.ready := armIn.ready && room && !fromRegisters
  private val taken = armIn.valid && armIn.ready
  when(taken && fromRegisters)(issued := true.B)
  private def armInput(in: ArmInput): Unit = {
    (0 until joints).foreach { j =>
      def reg(k: SampleKind) = sampleInputs(k)(j)(inputWidth(k) - 1, 0)
      in.q(j) := Mux(fromRegisters, reg(SampleKind.Angle), io.in.bits.q(j))
      in.qd(j) := Mux(fromRegisters, reg(SampleKind.Velocity).asSInt, io.in.bits.qd(j))
      in.qdd(j) := Mux(fromRegisters, reg(SampleKind.Acceleration).asSInt, io.in.bits.qdd(j))
    }
    in.payload.foreach(_ := active.get)
  }
  armInput(armIn.bits)

  // Each taken sample's sequence number and origin wait for its torques.
  private class Tag extends Bundle {
    val sequence = UInt(PayloadedArm.sequenceBits.W)
    val fromRegisters = Bool()
  }
  private val tags = Module(new Queue(new Tag, inFlight))
  tags.io.enq.valid := taken
  tags.io.enq.bits.sequence := sequence
  tags.io.enq.bits.fromRegisters := fromRegisters
  tags.io.deq.ready := armOut.valid
  private val toStream = armOut.valid && !tags.io.deq.bits.fromRegisters
  private val toRegisters = armOut.valid && tags.io.deq.bits.fromRegisters
  pending := pending + taken.asUInt - armOut.valid.asUInt
  outQueue.io.enq.valid := toStream
  outQueue.io.enq.bits.torques := armOut.bits
  outQueue.io.enq.bits.sequence.foreach(_ := tags.io.deq.bits.sequence)
  io.out <> outQueue.io.deq

  when(start) {
    busy := true.B
    done := false.B
    issued := false.B
  }.elsewhen(toRegisters) {
    busy := false.B
    done := true.B
    resultTau.zip(armOut.bits.tau).foreach { case (r, t) => r := t.pad(dataBits * tauWords).asUInt }
    resultFlags := armOut.bits.outOfRange.asUInt
    resultSequence := tags.io.deq.bits.sequence
  }

  // ---- commands, monitor status, counters, interrupt ----
  private def pulse(k: Command): Bool =
    RegNext(writing(Source.Control) && data(k.bit), false.B)
  private val clearCounters = pulse(Command.ClearCounters)
  private val snapshotReady = RegInit(true.B)
  host.foreach { h =>
    h.snapshot := pulse(Command.Snapshot)
    h.clear := pulse(Command.Clear)
    // Cleared by the write itself, so a status read right after the request already reads 0.
    when(writing(Source.Control) && data(Command.Snapshot.bit))(snapshotReady := false.B)
      .elsewhen(h.snapshotDone)(snapshotReady := true.B)
  }

  private val counters: Map[SampleCounter, UInt] = SampleCounter.all.map { k =>
    val count = RegInit(0.U(32.W))
    val step = k match {
      case SampleCounter.SamplesIn  => io.in.fire
      case SampleCounter.SamplesOut => io.out.fire
      case SampleCounter.OutOfRange => io.out.fire && io.out.bits.torques.outOfRange.asUInt.orR
      case SampleCounter.Stalls     => io.in.valid && !io.in.ready
    }
    when(clearCounters)(count := 0.U).elsewhen(step)(count := count +% 1.U)
    k -> count
  }.toMap

  private val eventBits = Event.all.map(_.bit).max + 1
  private val irqStatus = RegInit(0.U(eventBits.W))
  private val irqMask = RegInit(0.U(eventBits.W))
  private val inEvent = liveFlags.fold(false.B)(_.map(_(JointField.FlagBit.inEvent)).reduce(_ || _))
  liveFlags.foreach { flags =>
    def rose(bit: Int): Bool = flags.map(f => f(bit) && !RegNext(f(bit), false.B)).reduce(_ || _)
    val events = VecInit((0 until eventBits).map { bit =>
      Event.all.find(_.bit == bit).fold(false.B)(e => rose(Event.flagBit(e)))
    }).asUInt
    val cleared = Mux(writing(Source.InterruptStatus), data(eventBits - 1, 0), 0.U)
    irqStatus := (irqStatus & ~cleared) | events
    when(writing(Source.InterruptMask))(irqMask := data(eventBits - 1, 0))
  }
  io.irq := (irqStatus & irqMask).orR

  // ---- reads: the monitor block from the monitor's read port, every other register decoded here ----
  private val inMonitor = (host, monitor) match {
    case (Some(h), Some(m)) =>
      val block = map.block("monitor")
      require(
        block.block.span == 1 << m.addressBits && block.base % block.block.span == 0,
        s"register map ${map.name}: the monitor block must span the monitor's ${1 << m.addressBits} words, aligned"
      )
      h.readAddress := io.csr.address(m.addressBits - 1, 0)
      (io.csr.address >> m.addressBits).asUInt === (block.base >> m.addressBits).U
    case _ => false.B
  }

  private def value(r: PlacedRegister): Option[UInt] = r.register.source match {
    case Source.Constant                                            => Some(r.register.reset.U(32.W))
    case Source.Control | Source.PayloadCommit | Source.SampleStart => Some(0.U(32.W))
    case Source.Status =>
      Some(
        (snapshotReady.asUInt << ReducerLoadRegisters.snapshotReadyBit).asUInt |
          (inEvent.asUInt << ReducerLoadRegisters.inEventBit).asUInt
      )
    case Source.Counter(k)           => Some(counters(k))
    case Source.InterruptStatus      => Some(irqStatus)
    case Source.InterruptMask        => Some(irqMask)
    case Source.Monitor(_, _)        => None
    case Source.Parameter(k, w)      => staged.map(s => slice(s(k), w))
    case Source.PayloadSequence      => Some(sequence)
    case Source.SampleInput(k, j, w) => Some(slice(sampleInputs(k)(j), w))
    case Source.SampleStatus =>
      Some(
        (busy.asUInt << ReducerLoadRegisters.sampleBusyBit).asUInt |
          (done.asUInt << ReducerLoadRegisters.sampleDoneBit).asUInt
      )
    case Source.SampleTorque(j, w) => Some(slice(resultTau(j), w))
    case Source.SampleFlags        => Some(resultFlags)
    case Source.SampleSequence     => Some(resultSequence)
  }
  private val local = MuxLookup(io.csr.address, 0.U(32.W))(
    map.registers.flatMap(r => value(r).map(v => r.word.U -> v.pad(32)))
  )
  private val localData = RegNext(local)
  private val fromMonitor = RegNext(inMonitor, false.B)
  io.csr.readdatavalid := RegNext(io.csr.read, false.B)
  io.csr.readdata := Mux(fromMonitor, host.fold(0.U(32.W))(_.readData), localData)
}

object ReducerLoadCore {

  /** Output queues up to this deep are registers; deeper ones (long pipelines at II = 1) block RAM. */
  val registerQueueMax = 16
}
