package reducerload.monitor

import scala.collection.mutable.ArrayBuffer
import scala.util.Random

/** Seeded stimulus for the monitor: samples that dwell below, between and above the limits. */
object MonitorStimulus {

  /** A 3-joint monitor with three formats, exponents (3, 10/3, 1.5), dyadic and non-dyadic limits. */
  val threeJoints: MonitorParams = MonitorParams(
    jointNames = Seq("base", "elbow", "wrist"),
    torqueFormats = Seq(
      reducerload.fixedpoint.FixedFormat(8, 16),
      reducerload.fixedpoint.FixedFormat(6, 20),
      reducerload.fixedpoint.FixedFormat(4, 13)
    ),
    velocityFormats = Seq(
      reducerload.fixedpoint.FixedFormat(2, 16),
      reducerload.fixedpoint.FixedFormat(3, 18),
      reducerload.fixedpoint.FixedFormat(2, 12)
    ),
    repeatedPeakNm = Seq(40.0, 12.3, 3.5),
    momentaryPeakNm = Seq(100.0, 30.7, 7.25),
    lifeExponents = Seq(3.0, 10.0 / 3.0, 1.5),
    gearRatios = Seq(100.0, 81.0, 50.0),
    histogramBins = Seq(16, 10, 8),
    histogramBinWidthNm = Seq(16.0, 5.5, 1.9),
    samplePeriodS = 1e-3
  )

  private def uniform(rng: Random, lo: BigInt, hi: BigInt): BigInt =
    lo + (BigInt(62, rng.self) mod (hi - lo + 1))

  /**
   * One joint's torque for a dwell `mode`: 0 quiet, 1 between T_R and T_M, 2 above T_M, 3 within 3 codes of a
   * limit, 4 anywhere.
   */
  def torque(p: MonitorParams, j: Int, mode: Int, rng: Random): BigInt = {
    val max = p.torqueFormats(j).maxRaw // never the most negative code: a datapath clamps symmetrically
    val (r, m) = (p.repeatedPeakCode(j), p.momentaryPeakCode(j))
    val magnitude = mode match {
      case 0 => uniform(rng, 0, r)
      case 1 => uniform(rng, r + 1, m)
      case 2 => uniform(rng, m + 1, max)
      case 3 => (if (rng.nextBoolean()) r else m) + rng.nextInt(7) - 3
      case _ => uniform(rng, 0, max)
    }
    if (rng.nextBoolean()) magnitude else -magnitude
  }

  def velocity(p: MonitorParams, j: Int, mode: Int, rng: Random): BigInt = {
    val max = p.velocityFormats(j).maxRaw
    if (mode == 0 && rng.nextInt(4) == 0) BigInt(0) else uniform(rng, -max, max)
  }

  /** `n` samples in dwells of 1..24 samples per joint, 1 in 16 joint values flagged out of range. */
  def samples(p: MonitorParams, n: Int, rng: Random): IndexedSeq[MonitorSampleCodes] = {
    val modes = ArrayBuffer.fill(p.joints)(0)
    val left = ArrayBuffer.fill(p.joints)(0)
    IndexedSeq.fill(n) {
      (0 until p.joints).foreach { j =>
        if (left(j) == 0) { modes(j) = rng.nextInt(5); left(j) = 1 + rng.nextInt(24) }
        left(j) -= 1
      }
      MonitorSampleCodes(
        (0 until p.joints).map(j => torque(p, j, modes(j), rng)),
        (0 until p.joints).map(j => velocity(p, j, modes(j), rng)),
        (0 until p.joints).map(_ => rng.nextInt(16) == 0)
      )
    }
  }

  /**
   * Each joint's magnitudes around its limits, in this order (signs alternate): r-1, r, r+1, -(r-1), -r,
   * -(r+1), m-1, m, m+1, m+2, m, m+1 (r, m: the T_R and T_M codes). Expected: 8 samples above T_R; events
   * {m+1, m+2} and {m+1}: 2 events, the last of 1 sample, peak m+1.
   */
  def thresholdSamples(p: MonitorParams, rng: Random): IndexedSeq[MonitorSampleCodes] = {
    def row(j: Int): Seq[BigInt] = {
      val (r, m) = (p.repeatedPeakCode(j), p.momentaryPeakCode(j))
      Seq(r - 1, r, r + 1, -(r - 1), -r, -(r + 1), -(m - 1), m, -(m + 1), m + 2, -m, m + 1)
    }
    val rows = (0 until p.joints).map(row)
    rows.head.indices.map { i =>
      MonitorSampleCodes(
        rows.map(_(i)).toIndexedSeq,
        (0 until p.joints).map(j => velocity(p, j, 4, rng)),
        IndexedSeq.fill(p.joints)(false)
      )
    }
  }
}
