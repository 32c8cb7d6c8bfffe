package reducerload.load

import reducerload.testutil.CompiledParams
import reducerload.config.LoadParams
import reducerload.robot.RobotParams
import reducerload.arm.{ArmModel, ArmOutputCodes, ArmSample}
import reducerload.graph.SampleCodes

import scala.util.Random

/** Stimulus and the model for the joint-3 closed forms, in plain Scala (no simulator calls). */
object LoadChecks {

  /** A uniformly random sample inside the declared ranges, with a share of exact extremes. */
  def randomSample(r: RobotParams, rng: Random): ArmSample = {
    def within(m: Double) = rng.nextInt(10) match {
      case 0 => m
      case 1 => -m
      case 2 => 0.0
      case _ => (2 * rng.nextDouble() - 1) * m
    }
    def angle() = (rng.nextDouble() * 4 - 2) * math.Pi
    ArmSample(
      IndexedSeq.fill(3)(angle()),
      r.maxVelocity.map(within).toIndexedSeq,
      r.maxAcceleration.map(within).toIndexedSeq
    )
  }

  /** Like randomSample, but one velocity or acceleration is beyond its declared range (either sign). */
  def outOfRangeSample(r: RobotParams, rng: Random): ArmSample = {
    val s = randomSample(r, rng).toSeq.toArray
    val i = 3 + rng.nextInt(6)
    val limit = if (i < 6) r.maxVelocity(i - 3) else r.maxAcceleration(i - 6)
    s(i) = (if (rng.nextBoolean()) 1 else -1) * limit * (1.0 + 0.5 * rng.nextDouble() + 1e-3)
    ArmSample.fromRow(s.toSeq)
  }

  /**
   * The joint-3 design's bit-accurate model on planar3 samples: the arm model of its graph (one output, the
   * load).
   */
  final class Joint3Model(p: LoadParams) {
    val model = new ArmModel(p.arm)
    def encode(s: ArmSample): SampleCodes = model.encode(s)
    def evaluate(c: SampleCodes): ArmOutputCodes = model.evaluate(c)
    def loadOf(out: ArmOutputCodes): Double = model.torques(out).head
    def evaluate(s: ArmSample): Double = loadOf(evaluate(encode(s)))
  }
}
