package reducerload.monitor

/** One valid input sample as raw codes: per joint torque, velocity and out-of-range flag. */
final case class MonitorSampleCodes(
    torque: IndexedSeq[BigInt],
    velocity: IndexedSeq[BigInt],
    outOfRange: IndexedSeq[Boolean]
)

/** What the monitor's inputs carry in one clock cycle. */
final case class MonitorCycle(
    sample: Option[MonitorSampleCodes],
    snapshot: Boolean = false,
    clear: Boolean = false
)

/** Live state and shadow bank. */
final case class MonitorModelState(live: IndexedSeq[JointState], shadow: MonitorSnapshot)

/**
 * Bit-accurate model of [[ReducerMonitor]], in input cycles (the RTL applies each cycle's sample, snapshot
 * and clear together, `updateStage` cycles later, so its order of events is this one):
 *
 * shadow' = if (snapshot) live else shadow (the cycle's own sample is not in it) live' = update(if (clear)
 * cleared else live, sample) (the cycle's sample starts the new period)
 *
 * The per-sample rules read the thresholds, bin edges and power table from [[MonitorParams]], the same values
 * the RTL folds in. Every proven accumulator is checked against its width on every update: a value beyond it
 * means the 20-year proof's assumption (one sample per period) was broken.
 */
final class MonitorModel(val p: MonitorParams) {

  def initial: MonitorModelState =
    MonitorModelState((0 until p.joints).map(JointState.cleared(p, _)), MonitorSnapshot.cleared(p))

  def step(s: MonitorModelState, c: MonitorCycle): MonitorModelState = {
    c.sample.foreach(x =>
      require(
        x.torque.size == p.joints && x.velocity.size == p.joints && x.outOfRange.size == p.joints,
        s"MonitorModel: a sample needs ${p.joints} torques, velocities and flags"
      )
    )
    val shadow =
      if (c.snapshot) MonitorSnapshot((s.shadow.snapshotCount + 1) & RegisterMap.wordMask, s.live)
      else s.shadow
    val live = (0 until p.joints).map { j =>
      val start = if (c.clear) JointState.cleared(p, j) else s.live(j)
      c.sample.fold(start)(x => update(j, start, x.torque(j), x.velocity(j), x.outOfRange(j)))
    }
    MonitorModelState(live, shadow)
  }

  def run(cycles: Iterator[MonitorCycle]): MonitorModelState = cycles.foldLeft(initial)(step)

  /** One joint, one valid sample. */
  def update(j: Int, s: JointState, torque: BigInt, velocity: BigInt, outOfRange: Boolean): JointState = {
    val (tf, vf) = (p.torqueFormats(j), p.velocityFormats(j))
    require(
      tf.contains(torque),
      s"MonitorModel: joint ${p.jointNames(j)}: torque code $torque does not fit $tf"
    )
    require(
      vf.contains(velocity),
      s"MonitorModel: joint ${p.jointNames(j)}: velocity code $velocity does not fit $vf"
    )
    val next =
      if (outOfRange) s.copy(outOfRangeSamples = s.outOfRangeSamples + 1)
      else {
        val tau = p.magnitude(torque, tf)
        val qd = p.magnitude(velocity, vf)
        val aboveRepeated = tau > p.repeatedPeakCode(j)
        val aboveMomentary = tau > p.momentaryPeakCode(j)
        val bin = p.binOf(j, tau)
        val count = s.histogram(bin)
        val saturated = count == p.histogramMax
        val continuing = aboveMomentary && s.inEvent
        val newPeak = continuing && tau > s.lastEventPeak
        s.copy(
          samples = s.samples + 1,
          peakTorque = s.peakTorque.max(torque),
          minTorque = s.minTorque.min(torque),
          repeatedPeakSamples = s.repeatedPeakSamples + (if (aboveRepeated) 1 else 0),
          repeatedPeakSeen = s.repeatedPeakSeen || aboveRepeated,
          momentaryPeakEvents = s.momentaryPeakEvents + (if (aboveMomentary && !s.inEvent) 1 else 0),
          lastEventPeak = if (aboveMomentary && (!s.inEvent || newPeak)) tau else s.lastEventPeak,
          lastEventSpeed = if (aboveMomentary && (!s.inEvent || newPeak)) qd else s.lastEventSpeed,
          lastEventDuration =
            if (continuing) s.lastEventDuration + 1
            else if (aboveMomentary) BigInt(1)
            else s.lastEventDuration,
          inEvent = aboveMomentary,
          momentaryPeakSeen = s.momentaryPeakSeen || aboveMomentary,
          damageSum = s.damageSum + qd * p.powerTables(j).power(tau),
          speedSum = s.speedSum + qd,
          histogram = s.histogram.updated(bin, if (saturated) count else count + 1),
          histogramSaturated = s.histogramSaturated || saturated
        )
      }
    // The proof's premise, checked: no accumulator beyond its worst case over the sample budget
    // (which is below 2^width by construction).
    p.provenAccumulators.foreach { f =>
      val worst = p.maxIncrement(j, f) * p.sampleBudget
      require(
        next.field(f) <= worst,
        s"MonitorModel: joint ${p.jointNames(j)}: ${f.name} = ${next.field(f)} " +
          s"exceeds its proven worst case $worst (${p.accumulatorBits(j, f)} bits): more than the sample " +
          s"budget of ${p.sampleBudget} samples (${p.targetYears} years)"
      )
    }
    next
  }
}
