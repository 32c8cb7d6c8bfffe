package reducerload.monitor

/** One valid sample in physical units: torque (N·m), velocity (rad/s) and the out-of-range flag per joint. */
final case class MonitorSampleValues(
    torqueNm: IndexedSeq[Double],
    velocityRadS: IndexedSeq[Double],
    outOfRange: IndexedSeq[Boolean]
)

/**
 * The monitor's figures in double precision, straight from the definitions (docs/equations.md, "Reducer life
 * and limits"), with no table, code or integer: the independent check of [[MonitorModel]] and the RTL over
 * one period between clears. Only the limits, bin width, exponent and dt come from `p`.
 */
object MonitorReference {

  def summarize(
      p: MonitorParams,
      samples: Seq[MonitorSampleValues],
      rated: Seq[Option[RatedReducer]] = Nil
  ): Seq[JointSummary] =
    (0 until p.joints).map { j =>
      val inRange = samples.filter(s => !s.outOfRange(j))
      val tau = inRange.map(_.torqueNm(j))
      val speed = inRange.map(s => math.abs(s.velocityRadS(j)))
      val dt = p.samplePeriodS
      val exponent = p.lifeExponents(j)
      val sumP = tau.zip(speed).map { case (t, w) => w * math.pow(math.abs(t), exponent) * dt }.sum
      val sum1 = speed.map(_ * dt).sum
      val time = inRange.size * dt
      val avgTorque = if (sum1 > 0) Some(math.pow(sumP / sum1, 1.0 / exponent)) else None
      val avgSpeed = if (inRange.nonEmpty) Some(sum1 / time) else None
      val above = tau.map(t => math.abs(t) > p.momentaryPeakNm(j))
      // Events: maximal runs of consecutive in-range samples above T_M.
      val runs = above.indices.filter(i => above(i) && (i == 0 || !above(i - 1)))
      val last = runs.lastOption.map { start =>
        val run = (start until above.size).takeWhile(above)
        val peakAt = run.maxBy(i => (math.abs(tau(i)), -i)) // the first sample at the largest |tau|
        (math.abs(tau(peakAt)), run.size, speed(peakAt))
      }
      val bins = p.histogramBins(j)
      val histogram = tau
        .map(t => (math.abs(t) / p.histogramBinWidthNm(j)).floor.toInt.min(bins - 1))
        .groupBy(identity)
        .map { case (b, xs) => b -> xs.size }
      JointSummary(
        name = p.jointNames(j),
        samples = inRange.size,
        outOfRangeSamples = samples.size - inRange.size,
        runTimeS = time,
        peakNm = tau.maxOption,
        minNm = tau.minOption,
        avgTorqueNm = avgTorque,
        avgSpeedRadS = avgSpeed,
        repeatedPeakSamples = tau.count(t => math.abs(t) > p.repeatedPeakNm(j)),
        momentaryPeakEvents = runs.size,
        lastEventPeakNm = last.map(_._1),
        lastEventDurationSamples = last.fold(0)(_._2),
        lastEventSpeedRadS = last.map(_._3),
        histogram = (0 until bins).map(b => BigInt(histogram.getOrElse(b, 0))),
        damageSum = sumP,
        speedSumRad = sum1,
        lifeHours = MonitorSummary.life(p, j, avgTorque, avgSpeed, rated.lift(j).flatten)
      )
    }

  /** The physical values of a code sample. */
  def values(p: MonitorParams, s: MonitorSampleCodes): MonitorSampleValues =
    MonitorSampleValues(
      (0 until p.joints).map(j => p.torqueFormats(j).toDouble(s.torque(j))),
      (0 until p.joints).map(j => p.velocityFormats(j).toDouble(s.velocity(j))),
      s.outOfRange
    )
}
