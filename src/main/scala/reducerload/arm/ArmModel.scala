package reducerload.arm

import reducerload.fixedpoint.{FixedFormat, Rounding}
import reducerload.graph.{GraphModel, GraphReference, SampleCodes, Signal}
import reducerload.robot.{RigidBody, Vec3}

/**
 * One sample of joint state in SI units: angles (rad), velocities (rad/s), accelerations (rad/s^2), one each
 * per joint.
 */
final case class ArmSample(q: IndexedSeq[Double], qd: IndexedSeq[Double], qdd: IndexedSeq[Double]) {
  require(
    q.size == qd.size && q.size == qdd.size,
    s"ArmSample: ${q.size} angles, ${qd.size} velocities, ${qdd.size} accelerations"
  )

  /** Angles, then velocities, then accelerations: a trajectory row's order. */
  def toSeq: IndexedSeq[Double] = q ++ qd ++ qdd
}
object ArmSample {

  /** A sample from a row of angles, velocities and accelerations (n each, in that order). */
  def fromRow(row: Seq[Double]): ArmSample = {
    require(
      row.size % 3 == 0,
      s"ArmSample: a row of ${row.size} values is not n angles, n velocities and n accelerations"
    )
    val n = row.size / 3
    ArmSample(
      row.slice(0, n).toIndexedSeq,
      row.slice(n, 2 * n).toIndexedSeq,
      row.slice(2 * n, 3 * n).toIndexedSeq
    )
  }
}

/** Raw output of one sample: torque codes and the per-joint out-of-range flags. */
final case class ArmOutputCodes(tau: IndexedSeq[BigInt], outOfRange: IndexedSeq[Boolean])

/** Bit-accurate model of [[ArmDatapath]], and the conversions between SI values and codes. */
final class ArmModel(val p: ArmParams) {
  private val numerics = p.numerics
  private val graphModel = new GraphModel(p.analysis)
  private val turn = BigInt(1) << numerics.angleBits

  /** The datapath for one sample of port codes: clamp, the graph, the output stage. */
  def evaluate(in: SampleCodes): ArmOutputCodes = {
    def clamp(x: BigInt, limit: BigInt) = FixedFormat.clamp(x, -limit, limit)
    val (qd, qdFlags) = in.velocities.zip(numerics.velocityLimitRaw).map { case (x, l) => clamp(x, l) }.unzip
    val (qdd, qddFlags) =
      in.accelerations.zip(numerics.accelerationLimitRaw).map { case (x, l) => clamp(x, l) }.unzip
    val (parameters, parameterFlags) = numerics.parameters.map { s =>
      val (lo, hi) = numerics.parameterLimitRaw(s)
      val (v, outside) = FixedFormat.clamp(in.parameters(s), lo, hi)
      (s -> v, outside)
    }.unzip
    val out = graphModel.outputs(SampleCodes(in.angles, qd, qdd, parameters.toMap))
    // A clamped run-time parameter (payload, gravity) changes every torque: every joint is flagged.
    val saturated = out.exists(_._2) || parameterFlags.exists(identity)
    ArmOutputCodes(out.map(_._1), qdFlags.zip(qddFlags).map { case (a, b) => a || b || saturated })
  }

  /** Binary angle code of an angle in radians, any real value (wraps modulo one turn). */
  def angleCode(rad: Double): BigInt = {
    require(!rad.isNaN && !rad.isInfinite, s"angle $rad is not a finite number")
    val turns = rad / (2 * math.Pi)
    FixedFormat(62, numerics.angleBits).quantize(turns - math.floor(turns), Rounding.HalfUp).mod(turn)
  }

  /** Port codes of a sample (round to nearest), with no payload; values beyond a port's format saturate. */
  def encode(s: ArmSample): SampleCodes = encode(s, RigidBody.massless)

  /**
   * Port codes of a sample (round to nearest) computed with `payload` (in the payload frame; ignored by a
   * design without one); values beyond a port's format saturate at it.
   */
  def encode(s: ArmSample, payload: RigidBody): SampleCodes = encode(s, payload, p.chain.gravity)

  /**
   * Port codes of a sample computed with `payload` and the gravity `gravity` (m/s^2, base coordinates;
   * ignored by a design whose gravity is folded).
   */
  def encode(s: ArmSample, payload: RigidBody, gravity: Vec3): SampleCodes = {
    require(
      s.q.size == p.chain.size,
      s"a sample of ${s.q.size} joints for the ${p.chain.size}-joint ${p.chain.name}"
    )
    def code(x: Double, f: FixedFormat) = f.fromDouble(x, Rounding.HalfUp)._1
    SampleCodes(
      s.q.map(angleCode),
      s.qd.map(code(_, numerics.velocityPortFormat)),
      s.qdd.map(code(_, numerics.accelerationPortFormat)),
      parameterValues(payload, gravity).map { case (sig, v) =>
        sig -> code(v, numerics.parameterFormats(sig))
      }
    )
  }

  /**
   * The run-time parameters' values (SI units) for `payload` and `gravity`, as [[encode]] codes them: what a
   * double-precision reference of the graph takes ([[reducerload.graph.GraphReference]]).
   */
  def parameterValues(payload: RigidBody, gravity: Vec3): Map[Signal.Parameter, Double] =
    p.payload.fold(Map.empty[Signal.Parameter, Double])(_.values(p.chain, payload)) ++
      p.gravity.fold(Map.empty[Signal.Parameter, Double])(_.values(gravity))

  /** Torques in N·m. */
  def torques(out: ArmOutputCodes): IndexedSeq[Double] = out.tau.map(p.analysis.outputPortFormat.toDouble)

  /** Torques (N·m) of a sample with no payload, as [[encode]] codes it. */
  def evaluate(s: ArmSample): IndexedSeq[Double] = torques(evaluate(encode(s)))

  /**
   * The graph's torques in double precision for the sample [[evaluate]] computes (no payload, the chain's
   * gravity): what the derived error bound bounds the distance from.
   */
  def reference(s: ArmSample): IndexedSeq[Double] =
    GraphReference.outputs(p.graph, s.q, s.qd, s.qdd, parameterValues(RigidBody.massless, p.chain.gravity))
}
