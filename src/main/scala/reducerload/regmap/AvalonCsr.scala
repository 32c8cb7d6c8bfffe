package reducerload.regmap

import chisel3._
import chisel3.util.MuxLookup
import reducerload.arm.{ArmIO, ArmParams}
import reducerload.monitor.{JointField, MonitorParams, MonitoredArm}
import reducerload.pipeline.MultiplierImpl

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

/** [[MonitoredArmAvalon]]'s ports: the datapath's sample streams, the register slave, the interrupt. */
class MonitoredArmAvalonIO(p: ArmParams, map: CsrMap) extends ArmIO(p) {
  val csr = new AvalonSlave(map.addressBits)

  /** High while (irq.status & irq.mask) != 0 (an Avalon interrupt sender, level). */
  val irq = Output(Bool())
}

/**
 * The monitored arm ([[MonitoredArm]]) behind the register map `map` ([[ReducerLoadRegisters]]): the decoder
 * is generated from the map's layout and each register's [[Source]]; nothing here restates an address.
 *
 * Control pulses reach the monitor one clock after the write. The monitor block's words pass straight to the
 * monitor's read port (the block starts at a multiple of its power-of-two span, so the low address bits are
 * the monitor's word address). Counters count on the sample streams and wrap modulo 2^32. An interrupt event
 * is the rise of a live monitor flag on any joint; a write of 1 to a status bit clears it, and an event in
 * the same clock wins.
 */
class MonitoredArmAvalon(val p: ArmParams, val monitor: MonitorParams, val map: CsrMap)(implicit
    multiplierImpl: MultiplierImpl
) extends Module {
  import ReducerLoadRegisters.{Command, Event}
  override def desiredName = s"MonitoredArmAvalon_${p.tag}"
  val io = IO(new MonitoredArmAvalonIO(p, map))

  private val arm = Module(new MonitoredArm(p, monitor, liveFlags = true))
  arm.io.in <> io.in
  io.out := arm.io.out

  private def only(source: Source): PlacedRegister = map.registers.filter(_.register.source == source) match {
    case Seq(r) => r
    case rs =>
      throw new IllegalArgumentException(s"register map ${map.name}: ${rs.size} registers of $source")
  }
  private def at(r: PlacedRegister): Bool = io.csr.address === r.word.U

  // ---- writes ----
  private val write = io.csr.write
  private val data = io.csr.writedata
  private def requested(k: Command): Bool = write && at(only(Source.Control)) && data(k.bit)
  private def pulse(k: Command): Bool = RegNext(requested(k), false.B)
  private val snapshot = pulse(Command.Snapshot)
  private val clearCounters = pulse(Command.ClearCounters)
  arm.io.host.snapshot := snapshot
  arm.io.host.clear := pulse(Command.Clear)

  private val snapshotReady = RegInit(true.B)
  // Cleared by the write itself, so a status read right after the request already reads 0.
  when(requested(Command.Snapshot))(snapshotReady := false.B)
    .elsewhen(arm.io.host.snapshotDone)(snapshotReady := true.B)

  private val counters: Map[SampleCounter, UInt] = SampleCounter.all.map { k =>
    val count = RegInit(0.U(32.W))
    val step = k match {
      case SampleCounter.SamplesIn  => io.in.fire
      case SampleCounter.SamplesOut => arm.io.out.valid
      case SampleCounter.OutOfRange => arm.io.out.valid && arm.io.out.bits.outOfRange.asUInt.orR
      case SampleCounter.Stalls     => io.in.valid && !io.in.ready
    }
    when(clearCounters)(count := 0.U).elsewhen(step)(count := count +% 1.U)
    k -> count
  }.toMap

  private val eventBits = Event.all.map(_.bit).max + 1
  private val flags = arm.io.flags.get
  private def rose(bit: Int): Bool = flags.map(f => f(bit) && !RegNext(f(bit), false.B)).reduce(_ || _)
  private val inEvent = flags.map(_(JointField.FlagBit.inEvent)).reduce(_ || _)
  private val events = VecInit((0 until eventBits).map { bit =>
    Event.all.find(_.bit == bit).fold(false.B)(e => rose(Event.flagBit(e)))
  }).asUInt
  private val irqStatus = RegInit(0.U(eventBits.W))
  private val irqMask = RegInit(0.U(eventBits.W))
  private val statusCleared = Mux(write && at(only(Source.InterruptStatus)), data(eventBits - 1, 0), 0.U)
  irqStatus := (irqStatus & ~statusCleared) | events
  when(write && at(only(Source.InterruptMask)))(irqMask := data(eventBits - 1, 0))
  io.irq := (irqStatus & irqMask).orR

  // ---- reads: the monitor block from the monitor's read port, every other register decoded here ----
  private val monitorBlock = map.block("monitor")
  require(
    monitorBlock.block.span == 1 << monitor.addressBits && monitorBlock.base % monitorBlock.block.span == 0,
    s"register map ${map.name}: the monitor block must span the monitor's ${1 << monitor.addressBits} words, aligned"
  )
  arm.io.host.readAddress := io.csr.address(monitor.addressBits - 1, 0)
  private val inMonitor =
    (io.csr.address >> monitor.addressBits).asUInt === (monitorBlock.base >> monitor.addressBits).U

  private def value(r: PlacedRegister): Option[UInt] = r.register.source match {
    case Source.Constant => Some(r.register.reset.U(32.W))
    case Source.Control  => Some(0.U(32.W))
    case Source.Status =>
      Some(
        (snapshotReady.asUInt << ReducerLoadRegisters.snapshotReadyBit).asUInt |
          (inEvent.asUInt << ReducerLoadRegisters.inEventBit).asUInt
      )
    case Source.Counter(k)      => Some(counters(k))
    case Source.InterruptStatus => Some(irqStatus)
    case Source.InterruptMask   => Some(irqMask)
    case Source.Monitor(_, _)   => None
    case _                      => Some(0.U(32.W)) // the payload and sample blocks: the wrapper's (issue 32)
  }
  private val local = MuxLookup(io.csr.address, 0.U(32.W))(
    map.registers.flatMap(r => value(r).map(v => r.word.U -> v.pad(32)))
  )
  private val localData = RegNext(local)
  private val fromMonitor = RegNext(inMonitor)
  io.csr.readdatavalid := RegNext(io.csr.read, false.B)
  io.csr.readdata := Mux(fromMonitor, arm.io.host.readData, localData)
}
