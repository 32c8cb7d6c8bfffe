package reducerload.monitor

import chisel3._
import chisel3.util.Valid
import reducerload.pipeline.MultiplierImpl

/**
 * Reducer life and limit monitor for `p.joints` joints, beside any torque datapath: takes a `Valid` sample of
 * every joint's torque and velocity codes, keeps per joint the peaks, limit counters, momentary-peak events,
 * damage sums and histogram ([[JointMonitor]]), and gives the host a double-buffered view: `snapshot` copies
 * the live state of every joint into the shadow bank in one clock, `clear` resets the live state, and the
 * host reads the shadow bank by word address (`p.registerMap`).
 *
 * Timing in input cycles (docs/monitor.md): a snapshot pulsed in cycle t holds every valid sample of cycles
 * before t, none from t on; a clear pulsed in cycle t makes the sample of cycle t the first of the new
 * period. Both together: read-and-reset with no sample lost or counted twice. With `liveFlags`, `io.flags`
 * gives every joint's live flags (a bus wrapper's interrupt sources).
 */
class ReducerMonitor(val p: MonitorParams, liveFlags: Boolean = false)(implicit
    multiplierImpl: MultiplierImpl
) extends Module {
  override def desiredName = s"ReducerMonitor_${p.joints}j"
  val io = IO(new Bundle {
    val in = Flipped(Valid(new MonitorSample(p)))
    val host = new MonitorHostPort(p)
    val flags = if (liveFlags) Some(Output(Vec(p.joints, UInt(JointField.FlagBit.count.W)))) else None
  })

  private val joints = (0 until p.joints).map { j =>
    val m = Module(new JointMonitor(p, j, liveFlags))
    m.io.in.valid := io.in.valid
    m.io.in.bits.torque := io.in.bits.torque(j)
    m.io.in.bits.velocity := io.in.bits.velocity(j)
    m.io.in.bits.outOfRange := io.in.bits.outOfRange(j)
    m.io.snapshot := io.host.snapshot
    m.io.clear := io.host.clear
    m
  }

  // The joints copy their live state at the update stage; the count moves in the same clock.
  private val snapshotAtUpdate =
    (0 until p.updateStage).foldLeft(io.host.snapshot)((v, _) => RegNext(v, false.B))
  private val snapshotCount = RegInit(0.U(32.W))
  when(snapshotAtUpdate)(snapshotCount := snapshotCount +% 1.U)
  io.host.snapshotDone := RegNext(snapshotAtUpdate, false.B)

  private def value(e: RegisterEntry): UInt = e.key match {
    case RegisterKey.Id              => (RegisterMap.idBase + p.joints).U((32 * e.words).W)
    case RegisterKey.SnapshotCount   => snapshotCount
    case RegisterKey.Joint(j, field) => joints(j).io.shadow.field(field, 32 * e.words)
  }
  private val words: Seq[UInt] = p.registerMap.entries.flatMap { e =>
    val v = value(e)
    (0 until e.words).map(i => v(32 * i + 31, 32 * i))
  }
  require(
    words.size == p.registerMap.words,
    "ReducerMonitor: register bank size differs from the register map"
  )
  // Padded to a power of two so every address selects a word (unused ones read 0).
  io.flags.foreach(f => f := VecInit(joints.map(_.io.flags.get)))
  private val bank = VecInit(words ++ Seq.fill((1 << p.addressBits) - words.size)(0.U(32.W)))
  io.host.readData := RegNext(bank(io.host.readAddress))
}
