package reducerload.load

import reducerload.sim.{Cycle, Stream}

import scala.util.Random

/** Stimulus and checks for the load datapath, in plain Scala (no simulator calls). */
object LoadChecks {

  /** A uniformly random sample inside the declared ranges, with a share of exact extremes. */
  def randomSample(r: RobotParams, rng: Random): JointSample = {
    def within(m: Double) = rng.nextInt(10) match {
      case 0 => m
      case 1 => -m
      case 2 => 0.0
      case _ => (2 * rng.nextDouble() - 1) * m
    }
    def angle() = (rng.nextDouble() * 4 - 2) * math.Pi
    JointSample(angle(), angle(), angle(), within(r.maxVelocity(0)), within(r.maxVelocity(1)), within(r.maxVelocity(2)),
      within(r.maxAcceleration(0)), within(r.maxAcceleration(1)), within(r.maxAcceleration(2)))
  }

  /** Like randomSample, but one velocity or acceleration is beyond its declared range (either sign). */
  def outOfRangeSample(r: RobotParams, rng: Random): JointSample = {
    val s = randomSample(r, rng).toSeq.toArray
    val i = 3 + rng.nextInt(6)
    val limit = if (i < 6) r.maxVelocity(i - 3) else r.maxAcceleration(i - 6)
    s(i) = (if (rng.nextBoolean()) 1 else -1) * limit * (1.0 + 0.5 * rng.nextDouble() + 1e-3)
    JointSample.fromSeq(s.toSeq)
  }

  final case class Verdict(mismatches: Seq[String], checked: Int)

  /** Every observed output equals the model's, at exactly `latency` cycles. */
  def checkAgainstModel(p: LoadParams, stim: IndexedSeq[Cycle[LoadInputCodes]], observed: IndexedSeq[Option[LoadOutputCodes]]): Verdict = {
    val model = new LoadDatapathModel(p)
    val expected = Stream.expected(stim, LoadDatapath.latency(p)).map(_.map(model.evaluate))
    Verdict(Stream.mismatches[LoadOutputCodes, LoadOutputCodes](expected, observed, _ == _), expected.count(_.isDefined))
  }
}
