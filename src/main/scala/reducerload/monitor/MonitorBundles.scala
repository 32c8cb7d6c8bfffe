package reducerload.monitor

import chisel3._
import chisel3.util.{Cat, MixedVec}

/**
 * One sample of every joint: raw torque codes (`p.torqueFormats`), raw velocity codes (`p.velocityFormats`)
 * and a per-joint out-of-range flag (a datapath with one flag per sample drives it to every joint).
 */
class MonitorSample(p: MonitorParams) extends Bundle {
  val torque = MixedVec(p.torqueFormats.map(f => SInt(f.width.W)))
  val velocity = MixedVec(p.velocityFormats.map(f => SInt(f.width.W)))
  val outOfRange = Vec(p.joints, Bool())
}

/** One joint's share of a [[MonitorSample]]. */
class MonitorJointSample(p: MonitorParams, j: Int) extends Bundle {
  val torque = SInt(p.torqueFormats(j).width.W)
  val velocity = SInt(p.velocityFormats(j).width.W)
  val outOfRange = Bool()
}

/**
 * Host side: `snapshot` and `clear` are one-clock pulses (see docs/monitor.md for exactly which samples each
 * sees); `snapshotDone` is high in the first cycle the shadow bank holds a snapshot; `readAddress` (32-bit
 * word address) gives `readData` one clock later (an Avalon-MM slave with fixed read latency 1; reads have no
 * side effects, so `read` need not be decoded).
 */
class MonitorHostPort(p: MonitorParams) extends Bundle {
  val snapshot = Input(Bool())
  val clear = Input(Bool())
  val snapshotDone = Output(Bool())
  val readAddress = Input(UInt(p.addressBits.W))
  val readData = Output(UInt(32.W))
}

/** One joint's state registers (live or shadow), fields as in [[JointState]]. */
class JointMonitorState(p: MonitorParams, j: Int) extends Bundle {
  private def u(f: JointField) = UInt(p.fieldWidth(j, f).W)
  val samples = u(JointField.Samples)
  val outOfRangeSamples = u(JointField.OutOfRangeSamples)
  val peakTorque = SInt(p.fieldWidth(j, JointField.PeakTorque).W)
  val minTorque = SInt(p.fieldWidth(j, JointField.MinTorque).W)
  val repeatedPeakSamples = u(JointField.RepeatedPeakSamples)
  val momentaryPeakEvents = u(JointField.MomentaryPeakEvents)
  val lastEventPeak = u(JointField.LastEventPeak)
  val lastEventDuration = u(JointField.LastEventDuration)
  val lastEventSpeed = u(JointField.LastEventSpeed)
  val repeatedPeakSeen = Bool()
  val momentaryPeakSeen = Bool()
  val inEvent = Bool()
  val histogramSaturated = Bool()
  val damageSum = u(JointField.DamageSum)
  val speedSum = u(JointField.SpeedSum)
  val histogram = Vec(p.histogramBins(j), UInt(p.histogramBitsPerJoint.W))

  /** A field's bits for the register bank, sign- or zero-extended to `width` bits. */
  def field(f: JointField, width: Int): UInt = {
    def zero(x: UInt) = x.pad(width)
    def sign(x: SInt) = x.pad(width).asUInt
    f match {
      case JointField.Samples             => zero(samples)
      case JointField.OutOfRangeSamples   => zero(outOfRangeSamples)
      case JointField.PeakTorque          => sign(peakTorque)
      case JointField.MinTorque           => sign(minTorque)
      case JointField.RepeatedPeakSamples => zero(repeatedPeakSamples)
      case JointField.MomentaryPeakEvents => zero(momentaryPeakEvents)
      case JointField.LastEventPeak       => zero(lastEventPeak)
      case JointField.LastEventDuration   => zero(lastEventDuration)
      case JointField.LastEventSpeed      => zero(lastEventSpeed)
      case JointField.Flags     => zero(Cat(histogramSaturated, inEvent, momentaryPeakSeen, repeatedPeakSeen))
      case JointField.DamageSum => zero(damageSum)
      case JointField.SpeedSum  => zero(speedSum)
      case JointField.HistogramBin(k) => zero(histogram(k))
    }
  }
}
