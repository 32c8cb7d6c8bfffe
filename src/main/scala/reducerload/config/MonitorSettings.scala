package reducerload.config

/**
 * The monitor's configuration keys (`monitor.*`) as written, before the arm is known. A per-joint value is
 * one number for every joint or one number per joint; an empty Seq stands for the key's keyword: `urdf` for
 * the limits (derived from the URDF's `<limit effort>`), `auto` for the bin width (from the joint's derived
 * torque range), `none` for the rated torque (no life figure). [[reducerload.monitor.MonitorConfig]] resolves
 * them against the arm; here only what needs no robot is checked, and every message names its key.
 *
 * @param enabled
 *   build the monitor beside the arm datapath (model rnea only)
 * @param exponent
 *   life exponent p per joint in [1, 10]: 3 strain-wave, 10/3 cycloidal (RV)
 * @param repeatedPeakNm
 *   T_R per joint, N·m (empty: `<limit effort>`)
 * @param momentaryPeakNm
 *   T_M per joint, N·m (empty: `momentaryPeakFactor` x `<limit effort>`)
 * @param momentaryPeakFactor
 *   T_M / `<limit effort>` when T_M comes from the URDF
 * @param gearRatio
 *   reduction ratio i per joint (input speed = i x joint speed)
 * @param samplePeriodS
 *   time between valid samples, s (dt of the sums, basis of the 20-year proof)
 * @param histogramBins
 *   \|torque| histogram bins per joint
 * @param histogramBinWidthNm
 *   bin width per joint, N·m (empty: torque range / bins, rounded up to a torque LSB)
 * @param ratedTorqueNm
 *   catalogue rated output torque T_N per joint (empty: no life figure)
 * @param ratedInputSpeedRpm
 *   catalogue rated input speed n_N, rpm
 * @param ratedLifeHours
 *   catalogue rated life L_n (L50), h
 */
final case class MonitorSettings(
    enabled: Boolean = false,
    exponent: Seq[Double] = Seq(3.0),
    repeatedPeakNm: Seq[Double] = Nil,
    momentaryPeakNm: Seq[Double] = Nil,
    momentaryPeakFactor: Double = 1.5,
    gearRatio: Seq[Double] = Seq(100.0),
    samplePeriodS: Double = 1e-3,
    histogramBins: Seq[Int] = Seq(16),
    histogramBinWidthNm: Seq[Double] = Nil,
    ratedTorqueNm: Seq[Double] = Nil,
    ratedInputSpeedRpm: Double = 2000.0,
    ratedLifeHours: Double = 35000.0
) {
  import MonitorSettings.finite

  private def each(key: String, values: Seq[Double], rule: String)(ok: Double => Boolean): Unit =
    values.foreach(v => require(finite(v) && ok(v), s"monitor.$key must be $rule, got $v"))

  require(exponent.nonEmpty, "monitor.exponent needs a number or one per joint")
  each("exponent", exponent, "in [1, 10] (3: strain-wave, 3.3333333333333335 = 10/3: cycloidal/RV)")(p =>
    p >= 1 && p <= 10
  )
  each("repeated-peak", repeatedPeakNm, "a positive torque in N·m (or urdf)")(_ > 0)
  each("momentary-peak", momentaryPeakNm, "a positive torque in N·m (or urdf)")(_ > 0)
  require(
    finite(momentaryPeakFactor) && momentaryPeakFactor > 1 && momentaryPeakFactor <= 10,
    s"monitor.momentary-peak-factor must be in (1, 10] (T_M must exceed T_R = <limit effort>), got $momentaryPeakFactor"
  )
  require(gearRatio.nonEmpty, "monitor.gear-ratio needs a number or one per joint")
  each("gear-ratio", gearRatio, "a positive ratio")(_ > 0)
  require(
    finite(samplePeriodS) && samplePeriodS >= 1e-9 && samplePeriodS <= 10,
    s"monitor.sample-period must be in [1e-9, 10] s, got $samplePeriodS"
  )
  require(histogramBins.nonEmpty, "monitor.histogram-bins needs a number or one per joint")
  histogramBins.foreach(b => require(b >= 1 && b <= 256, s"monitor.histogram-bins must be in 1..256, got $b"))
  each("histogram-bin-width", histogramBinWidthNm, "a positive width in N·m (or auto)")(_ > 0)
  each("rated-torque", ratedTorqueNm, "a positive torque in N·m (or none)")(_ > 0)
  require(
    finite(ratedInputSpeedRpm) && ratedInputSpeedRpm > 0,
    s"monitor.rated-input-speed must be a positive speed in rpm, got $ratedInputSpeedRpm"
  )
  require(
    finite(ratedLifeHours) && ratedLifeHours > 0,
    s"monitor.rated-life must be a positive number of hours, got $ratedLifeHours"
  )
}

object MonitorSettings {
  private def finite(x: Double) = !x.isNaN && !x.isInfinite
}
