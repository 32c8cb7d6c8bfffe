package reducerload.arm

import reducerload.robot.{Mat3, RigidBody, Vec3}

/**
 * The ten payload columns of a trajectory or golden trace, as robot controllers state load data: mass (kg),
 * centre of mass (m, in the payload frame) and inertia tensor about the centre of mass (kg m^2, in the
 * payload frame's axes; the six entries of the symmetric tensor).
 */
object PayloadColumns {
  val names: Seq[String] = Seq(
    "payload_mass",
    "payload_cx",
    "payload_cy",
    "payload_cz",
    "payload_ixx",
    "payload_ixy",
    "payload_ixz",
    "payload_iyy",
    "payload_iyz",
    "payload_izz"
  )

  /** The payload of one row's ten values, in the order of `names`. */
  def body(v: Seq[Double]): RigidBody = {
    require(v.size == names.size, s"a payload has ${names.size} values, got ${v.size}")
    RigidBody(v(0), Vec3(v(1), v(2), v(3)), Mat3.symmetric(v(4), v(5), v(6), v(7), v(8), v(9)))
  }

  /** The ten values of a payload, in the order of `names`. */
  def values(b: RigidBody): Seq[Double] =
    Seq(b.mass, b.com.x, b.com.y, b.com.z, b.inertia(0, 0), b.inertia(0, 1), b.inertia(0, 2)) ++
      Seq(b.inertia(1, 1), b.inertia(1, 2), b.inertia(2, 2))
}
