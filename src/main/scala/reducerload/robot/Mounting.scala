package reducerload.robot

/**
 * How the robot's base is mounted: its orientation in the world as URDF roll, pitch, yaw (rad; R = Rz(yaw)
 * Ry(pitch) Rx(roll) maps base to world coordinates). The world is the one in which the chain's own gravity
 * holds: (0, 0, -g) for a URDF robot (z up), (+g, 0, 0) for the built-in planar3. So the gravity the dynamics
 * use, in base coordinates, is R^T times the chain's own: folded at elaboration like every robot constant.
 *
 * Named mountings: `floor` (0, 0, 0; the default, the chain unchanged), `ceiling` (pi, 0, 0: upside down, a
 * URDF robot's gravity along base +z) and `wall` (0, pi/2, 0: the base's z axis horizontal along world +x,
 * its x axis pointing down, so a URDF robot's gravity is along base +x).
 */
final case class Mounting(roll: Double, pitch: Double, yaw: Double) {
  Seq("roll" -> roll, "pitch" -> pitch, "yaw" -> yaw).foreach { case (what, a) =>
    require(
      !a.isNaN && math.abs(a) <= Mounting.maxAngle,
      s"${Mounting.setting}: $what must be an angle in [-2 pi, 2 pi] rad, got $a"
    )
  }

  /**
   * Base to world (cos and sin snapped as in URDF origins: the named mountings give exact zeros and ones).
   */
  def rotation: Mat3 = Mat3.rpy(roll, pitch, yaw)

  def isFloor: Boolean = this == Mounting.floor

  /** `g`, the chain's own gravity (base coordinates at floor mounting), for a base mounted so. */
  def gravity(g: Vec3): Vec3 = if (isFloor) g else rotation.transpose * g

  /** The name of a named mounting. */
  def name: Option[String] = Mounting.named.collectFirst { case (n, m) if m == this => n }

  override def toString: String = name.getOrElse(s"base-rpy ($roll, $pitch, $yaw) rad")
}

object Mounting {
  val setting: String = "robot.base-rpy"
  val maxAngle: Double = 2 * math.Pi
  val floor: Mounting = Mounting(0, 0, 0)
  val ceiling: Mounting = Mounting(math.Pi, 0, 0)
  val wall: Mounting = Mounting(0, math.Pi / 2, 0)
  val named: Seq[(String, Mounting)] = Seq("floor" -> floor, "ceiling" -> ceiling, "wall" -> wall)
}
