package reducerload.monitor

import chisel3._
import chisel3.util._
import reducerload.fixedpoint.{FixedFormat, FixedHw}
import reducerload.graph.SampleCodes
import reducerload.pipeline.{MemoryDelay, MultiplierImpl}
import reducerload.arm.{ArmDatapath, ArmIO, ArmInput, ArmOutput, ArmOutputCodes, ArmParams, ArmSample}

/**
 * Every joint torque of an arm ([[ArmDatapath]]) and, beside it, the reducer life and limit monitor
 * ([[ReducerMonitor]]) fed from the datapath's output: each sample's torques, its velocities clamped to the
 * declared ranges (re-derived from the input codes exactly as the datapath clamps them, and delayed to meet
 * the torques), and the sample's out-of-range flag on every joint (flagged samples are counted, not
 * accumulated). The datapath flags the joint whose qd or qdd was clamped, but every joint's torque depends on
 * every joint's motion (RNEA: the inner joints carry the outer bodies, the outer joints move on the inner
 * ones), so a clamped input makes every torque of that sample a torque of other inputs: none of them is load
 * to accumulate.
 *
 * `io.in` and `io.out` are the datapath's ports; `io.host` is the monitor's (snapshot, clear, read port).
 * Host pulses act in the monitor's input cycles, which are the datapath's output cycles: a snapshot pulsed in
 * cycle t holds the samples whose torques left `io.out` before cycle t, i.e. the samples given on `io.in`
 * before cycle t - `p.latency`.
 */
class MonitoredArm(val p: ArmParams, val monitor: MonitorParams, liveFlags: Boolean = false)(implicit
    multiplierImpl: MultiplierImpl
) extends Module {
  MonitoredArm.check(p, monitor)
  override def desiredName = s"MonitoredArm_${p.tag}"
  val io = IO(new MonitoredArmIO(p, monitor, liveFlags))
  private val joints = p.chain.size
  private val numerics = p.numerics

  private val datapath = Module(new ArmDatapath(p))
  datapath.io.in <> io.in
  io.out := datapath.io.out

  // The datapath's own input stage, for the velocities only: clamp and register (cycle 1), then delay
  // to the cycle the torques leave (long delays in block RAM, as in the datapath).
  private val velocities = (0 until joints).map { j =>
    val limit = numerics.velocityLimitRaw(j)
    val (clamped, _) = FixedHw.clamp(io.in.bits.qd(j), -limit, limit, numerics.velocityFormats(j).width)
    MemoryDelay.balanced(
      FixedHw.delay(clamped, ArmDatapath.inputCycle),
      p.latency - ArmDatapath.inputCycle,
      p.memoryDelayMinCycles
    )
  }

  private val sampleOutOfRange = datapath.io.out.bits.outOfRange.asUInt.orR

  private val reducers = Module(new ReducerMonitor(monitor, liveFlags))
  reducers.io.in.valid := datapath.io.out.valid
  (0 until joints).foreach { j =>
    val width = monitor.torqueFormats(j).width
    val tau = datapath.io.out.bits.tau(j)
    // Same fraction bits; the code fits the joint's output format (saturated there), so dropping
    // top bits only drops copies of the sign, and widening is a sign extension.
    reducers.io.in.bits.torque(j) := (if (tau.getWidth > width) tau(width - 1, 0).asSInt else tau.pad(width))
    reducers.io.in.bits.velocity(j) := velocities(j)
    reducers.io.in.bits.outOfRange(j) := sampleOutOfRange
  }
  io.host <> reducers.io.host
  io.flags.foreach(_ := reducers.io.flags.get)
}

/**
 * [[MonitoredArm]]'s ports: the datapath's ([[ArmIO]]) and the monitor's host port; with `liveFlags`, every
 * joint's live flags (JointField.Flags' bits) for a bus wrapper's interrupt.
 */
class MonitoredArmIO(p: ArmParams, monitor: MonitorParams, liveFlags: Boolean = false) extends ArmIO(p) {
  val host = new MonitorHostPort(monitor)
  val flags = if (liveFlags) Some(Output(Vec(monitor.joints, UInt(JointField.FlagBit.count.W)))) else None
}

object MonitoredArm {

  /** The monitor must read the datapath's codes as they are: same joints, fraction bits, velocity formats. */
  def check(p: ArmParams, m: MonitorParams): Unit = {
    require(
      m.joints == p.chain.size,
      s"MonitoredArm: a ${m.joints}-joint monitor for the ${p.chain.size}-joint ${p.chain.name}"
    )
    (0 until m.joints).foreach { j =>
      val out = p.analysis.outputs(j).format
      val tf = m.torqueFormats(j)
      require(
        tf.fracBits == out.fracBits && tf.intBits >= out.intBits,
        s"MonitoredArm: joint ${j + 1}: monitor torque format $tf cannot hold the datapath's $out codes"
      )
      require(
        m.velocityFormats(j) == p.numerics.velocityFormats(j),
        s"MonitoredArm: joint ${j + 1}: monitor velocity format ${m.velocityFormats(j)} differs from the datapath's ${p.numerics.velocityFormats(j)}"
      )
    }
  }

  /**
   * What the monitor receives for one sample: the model's torques, the clamped velocity codes, the sample's
   * flag on every joint.
   */
  def monitorSample(p: ArmParams, in: SampleCodes, out: ArmOutputCodes): MonitorSampleCodes = {
    val velocities =
      in.velocities.zip(p.numerics.velocityLimitRaw).map { case (x, l) => FixedFormat.clamp(x, -l, l)._1 }
    MonitorSampleCodes(
      out.tau,
      velocities.toIndexedSeq,
      IndexedSeq.fill(p.chain.size)(out.outOfRange.exists(identity))
    )
  }
}
