package reducerload.graph

import reducerload.cordic.CordicParams
import reducerload.fixedpoint.{FixedFormat, Rounding}

/** A closed interval of reals: the exact values a node can take over the declared input ranges. */
final case class Interval(lo: Double, hi: Double) {
  require(
    lo <= hi && !lo.isNaN && !hi.isNaN && !lo.isInfinite && !hi.isInfinite,
    s"Interval: [$lo, $hi] is not a finite interval"
  )
  def maxAbs: Double = math.max(math.abs(lo), math.abs(hi))
  def +(o: Interval): Interval = Interval(lo + o.lo, hi + o.hi)
  def -(o: Interval): Interval = Interval(lo - o.hi, hi - o.lo)
  def unary_- : Interval = Interval(-hi, -lo)
  def *(o: Interval): Interval = {
    val p = Seq(lo * o.lo, lo * o.hi, hi * o.lo, hi * o.hi)
    Interval(p.min, p.max)
  }
  def squared: Interval = {
    val m = maxAbs * maxAbs
    if (lo <= 0 && hi >= 0) Interval(0, m) else Interval(math.min(lo * lo, hi * hi), m)
  }
}
object Interval {
  def symmetric(m: Double): Interval = Interval(-m, m)
  def point(v: Double): Interval = Interval(v, v)
}

/**
 * The number formats a graph is computed in: per-joint declared ranges, the sin/cos unit, and the fraction
 * bits of each kind of value. The rules that turn them into every node's format live in [[Analysis]]; nothing
 * else decides a width.
 *
 * @param velocityLimits
 *   declared max |qd_j|, rad/s, one per joint (their number is the joint count)
 * @param accelerationLimits
 *   declared max |qdd_j|, rad/s^2, one per joint
 * @param parameterRanges
 *   the declared interval of each run-time inertial parameter (the payload's), SI units
 */
final case class Numerics(
    velocityLimits: Seq[Double],
    accelerationLimits: Seq[Double],
    cordic: CordicParams,
    velocityFracBits: Int,
    accelerationFracBits: Int,
    constantFracBits: Int,
    internalFracBits: Int,
    outputFracBits: Int,
    productRounding: Rounding,
    parameterRanges: Map[Signal.Parameter, Interval] = Map.empty
) {
  require(
    velocityLimits.size == accelerationLimits.size,
    s"Numerics: ${velocityLimits.size} velocity limits but ${accelerationLimits.size} " +
      s"acceleration limits (one each per joint)"
  )
  reducerload.robot.RobotParams.checkRanges(velocityLimits, accelerationLimits)
  Numerics.checkFracBits(
    velocityFracBits,
    accelerationFracBits,
    constantFracBits,
    internalFracBits,
    outputFracBits
  )

  def joints: Int = velocityLimits.size
  def angleBits: Int = cordic.angleBits

  /** Each joint's velocity and acceleration format, from its declared range. */
  val velocityFormats: Seq[FixedFormat] = velocityLimits.map(FixedFormat.forRange(_, velocityFracBits))
  val accelerationFormats: Seq[FixedFormat] =
    accelerationLimits.map(FixedFormat.forRange(_, accelerationFracBits))

  /** The ports carry every joint in the widest joint's format. */
  val velocityPortFormat: FixedFormat = velocityFormats.maxBy(_.width)
  val accelerationPortFormat: FixedFormat = accelerationFormats.maxBy(_.width)

  /**
   * Declared limits as codes (round to nearest, as inputs are converted): codes beyond them are clamped and
   * flagged.
   */
  val velocityLimitRaw: Seq[BigInt] =
    velocityLimits.zip(velocityFormats).map { case (v, f) => f.quantize(v, Rounding.HalfUp) }
  val accelerationLimitRaw: Seq[BigInt] =
    accelerationLimits.zip(accelerationFormats).map { case (a, f) => f.quantize(a, Rounding.HalfUp) }

  parameterRanges.keys.foreach(s =>
    require(s.joint < joints, s"Numerics: run-time parameter $s of a joint beyond the $joints declared")
  )

  /**
   * The run-time parameters in port order: the inertial ones by joint, then as [[InertialParameter.all]];
   * then the gravity's x, y, z.
   */
  val parameters: IndexedSeq[Signal.Parameter] =
    ((0 until joints).flatMap(Signal.inertial) ++ Signal.gravity).filter(parameterRanges.contains)

  /**
   * Each run-time parameter's format (also its port's), from its declared range, with the products' fraction
   * bits: the first product that reads it keeps no more.
   */
  val parameterFormats: Map[Signal.Parameter, FixedFormat] =
    parameterRanges.map { case (s, r) => s -> FixedFormat.forRange(r.maxAbs, internalFracBits) }

  /** The port carries every parameter in the widest parameter's format (one fraction-bit count for all). */
  def parameterPortFormat: FixedFormat = parameterFormats.values.maxBy(_.width)

  /**
   * Each parameter's declared interval as codes (round to nearest): codes beyond it are clamped and flagged.
   */
  val parameterLimitRaw: Map[Signal.Parameter, (BigInt, BigInt)] = parameterRanges.map { case (s, r) =>
    val f = parameterFormats(s)
    s -> ((f.quantize(r.lo, Rounding.HalfUp), f.quantize(r.hi, Rounding.HalfUp)))
  }

  /** Half an angle code, in radians: inputs are rounded to the nearest code. */
  val angleError: Double = math.Pi / math.pow(2.0, angleBits)
}

object Numerics {

  /** The fraction-bit settings' own limits, checked wherever they are set. */
  def checkFracBits(velocity: Int, acceleration: Int, constant: Int, internal: Int, output: Int): Unit = {
    Seq(
      "velocity-frac-bits" -> velocity,
      "acceleration-frac-bits" -> acceleration,
      "constant-frac-bits" -> constant,
      "internal-frac-bits" -> internal,
      "output-frac-bits" -> output
    ).foreach { case (name, bits) =>
      require(bits >= 1 && bits <= 40, s"datapath.$name must be in 1..40, got $bits")
    }
    require(
      output <= internal,
      s"datapath.output-frac-bits ($output) must not exceed internal-frac-bits ($internal)"
    )
  }
}
