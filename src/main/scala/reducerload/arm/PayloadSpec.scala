package reducerload.arm

import reducerload.dynamics.{BodyInertia, Sym3, V3, VectorAlgebra}
import reducerload.graph.{InertialParameter, Interval, Signal}
import reducerload.robot.{RigidBody, SerialChain, Transform}

/**
 * The payload a design serves at run time: the declared set its ten inertial parameters lie in, and the frame
 * they are stated in. The parameters are graph inputs ([[Signal.Inertial]] of the last joint), so the range
 * and error analysis covers every payload in the set, and one design serves them all.
 *
 * The declared set is a box: mass in [0, maxMass], each coordinate of the centre of mass within comRadius of
 * the frame's origin, the inertia about the centre of mass within maxMass x maxGyrationRadius^2 per element
 * (diagonal elements non-negative). A physical payload of mass <= maxMass whose centre of mass lies within
 * comRadius of the origin and whose radius of gyration is at most maxGyrationRadius is in it.
 *
 * @param frame
 *   the link the payload is stated in (a link fixed to the last moving joint; the tip by default)
 * @param pose
 *   that link's frame in the last moving joint's frame
 */
final case class PayloadSpec(
    frame: String,
    pose: Transform,
    maxMass: Double,
    comRadius: Double,
    maxGyrationRadius: Double
) {
  // The settings' bounds are checked where they are read (PayloadSettings); these are the invariants.
  require(maxMass > 0 && comRadius >= 0 && maxGyrationRadius >= 0, s"PayloadSpec: no declared set in $this")

  /** Bound on every element of the inertia about the centre of mass, kg m^2. */
  def maxInertia: Double = maxMass * maxGyrationRadius * maxGyrationRadius

  /** The declared interval of one parameter. */
  def range(p: InertialParameter): Interval = p match {
    case InertialParameter.Mass                     => Interval(0, maxMass)
    case InertialParameter.Com(_)                   => Interval.symmetric(comRadius)
    case i: InertialParameter.Inertia if i.diagonal => Interval(0, maxInertia)
    case _: InertialParameter.Inertia               => Interval.symmetric(maxInertia)
  }

  /** The payload's joint in `chain`: the last. */
  def joint(chain: SerialChain): Int = chain.size - 1

  /** Every parameter's signal with its declared interval. */
  def ranges(chain: SerialChain): Map[Signal.Parameter, Interval] =
    Signal.inertial(joint(chain)).map(s => s -> range(s.parameter)).toMap

  /** A body's parameters in the payload frame, by signal (SI units). */
  def values(chain: SerialChain, body: RigidBody): Map[Signal.Parameter, Double] =
    Signal.inertial(joint(chain)).map(s => s -> PayloadSpec.value(body, s.parameter)).toMap

  /** What the payload adds at the last joint's origin, from its parameters as values of T. */
  def added[T](mass: T, com: V3[T], inertia: Sym3[T])(implicit va: VectorAlgebra[T]): BodyInertia[T] =
    BodyInertia.placed(pose, mass, com, inertia)

  /** `chain` with `body` (in the payload frame) merged into its last body: the payload as a constant. */
  def merged(chain: SerialChain, body: RigidBody): SerialChain = {
    val last = chain.joints.last
    chain.copy(joints = chain.joints.init :+ last.copy(body = last.body.merge(body.transformed(pose))))
  }
}

object PayloadSpec {

  /** One inertial parameter of `body`. */
  def value(body: RigidBody, p: InertialParameter): Double = p match {
    case InertialParameter.Mass              => body.mass
    case InertialParameter.Com(axis)         => body.com.toSeq(axis)
    case InertialParameter.Inertia(row, col) => body.inertia(row, col)
  }
}
