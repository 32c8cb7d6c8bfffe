package reducerload.monitor

import reducerload.monitor.JointField._

/**
 * One joint's monitor state as integers: what [[MonitorModel]] keeps, what the RTL's live and shadow
 * registers hold, and what a register-bank read decodes to. Codes as in [[MonitorParams]].
 */
final case class JointState(
    samples: BigInt,
    outOfRangeSamples: BigInt,
    peakTorque: BigInt,
    minTorque: BigInt,
    repeatedPeakSamples: BigInt,
    momentaryPeakEvents: BigInt,
    lastEventPeak: BigInt,
    lastEventDuration: BigInt,
    lastEventSpeed: BigInt,
    repeatedPeakSeen: Boolean,
    momentaryPeakSeen: Boolean,
    inEvent: Boolean,
    histogramSaturated: Boolean,
    damageSum: BigInt,
    speedSum: BigInt,
    histogram: Vector[BigInt]
) {

  def flags: BigInt = Seq(
    FlagBit.repeatedPeakSeen -> repeatedPeakSeen,
    FlagBit.momentaryPeakSeen -> momentaryPeakSeen,
    FlagBit.inEvent -> inEvent,
    FlagBit.histogramSaturated -> histogramSaturated
  ).collect { case (bit, true) => BigInt(1) << bit }.sum

  def field(f: JointField): BigInt = f match {
    case Samples             => samples
    case OutOfRangeSamples   => outOfRangeSamples
    case PeakTorque          => peakTorque
    case MinTorque           => minTorque
    case RepeatedPeakSamples => repeatedPeakSamples
    case MomentaryPeakEvents => momentaryPeakEvents
    case LastEventPeak       => lastEventPeak
    case LastEventDuration   => lastEventDuration
    case LastEventSpeed      => lastEventSpeed
    case Flags               => flags
    case DamageSum           => damageSum
    case SpeedSum            => speedSum
    case HistogramBin(k)     => histogram(k)
  }
}

object JointState {

  /**
   * The state after clear (and reset): nothing seen; peak and min start at the opposite ends of the format.
   */
  def cleared(p: MonitorParams, j: Int): JointState = {
    def start(f: JointField) = p.clearValue(j, f)
    JointState(
      samples = start(Samples),
      outOfRangeSamples = start(OutOfRangeSamples),
      peakTorque = p.torqueFormats(j).minRaw,
      minTorque = p.torqueFormats(j).maxRaw,
      repeatedPeakSamples = start(RepeatedPeakSamples),
      momentaryPeakEvents = start(MomentaryPeakEvents),
      lastEventPeak = 0,
      lastEventDuration = start(LastEventDuration),
      lastEventSpeed = 0,
      repeatedPeakSeen = false,
      momentaryPeakSeen = false,
      inEvent = p.clearInEvent,
      histogramSaturated = false,
      damageSum = start(DamageSum),
      speedSum = start(SpeedSum),
      histogram = Vector.fill(p.histogramBins(j))(BigInt(0))
    )
  }

  def fromFields(p: MonitorParams, j: Int, value: JointField => BigInt): JointState = {
    val flags = value(Flags)
    JointState(
      value(Samples),
      value(OutOfRangeSamples),
      value(PeakTorque),
      value(MinTorque),
      value(RepeatedPeakSamples),
      value(MomentaryPeakEvents),
      value(LastEventPeak),
      value(LastEventDuration),
      value(LastEventSpeed),
      flags.testBit(FlagBit.repeatedPeakSeen),
      flags.testBit(FlagBit.momentaryPeakSeen),
      flags.testBit(FlagBit.inEvent),
      flags.testBit(FlagBit.histogramSaturated),
      value(DamageSum),
      value(SpeedSum),
      (0 until p.histogramBins(j)).map(k => value(HistogramBin(k))).toVector
    )
  }
}

/** The shadow bank: every joint's state at a snapshot, and the snapshot's sequence number. */
final case class MonitorSnapshot(snapshotCount: BigInt, joints: IndexedSeq[JointState]) {

  def registerValue(p: MonitorParams)(key: RegisterKey): BigInt = key match {
    case RegisterKey.Id              => RegisterMap.idBase + p.joints
    case RegisterKey.SnapshotCount   => snapshotCount & RegisterMap.wordMask
    case RegisterKey.Joint(j, field) => joints(j).field(field)
  }

  /** The register bank's words, as the host reads them. */
  def bank(p: MonitorParams): IndexedSeq[BigInt] = p.registerMap.encode(registerValue(p))
}

object MonitorSnapshot {
  def cleared(p: MonitorParams): MonitorSnapshot =
    MonitorSnapshot(0, (0 until p.joints).map(JointState.cleared(p, _)))

  /** Decode a register bank read by the host; checks the id word. */
  def fromBank(p: MonitorParams, bank: IndexedSeq[BigInt]): MonitorSnapshot = {
    val values = p.registerMap.decode(bank)
    require(
      values(RegisterKey.Id) == RegisterMap.idBase + p.joints,
      f"register bank: monitor_id 0x${values(RegisterKey.Id)}%x is not a ${p.joints}-joint monitor"
    )
    MonitorSnapshot(
      values(RegisterKey.SnapshotCount),
      (0 until p.joints).map(j => JointState.fromFields(p, j, f => values(RegisterKey.Joint(j, f))))
    )
  }
}
