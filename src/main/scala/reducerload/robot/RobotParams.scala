package reducerload.robot

/**
 * The arm, in SI units, and the declared input ranges the fixed-point formats are derived from. Joint angles
 * have no range: binary angles wrap, so every angle is in range.
 *
 * @param m3
 *   point mass at the end of link 3, kg
 * @param l1
 *   link lengths, m
 * @param g
 *   gravitational acceleration, m/s^2 (0 for an arm moving in a horizontal plane)
 * @param maxVelocity
 *   declared max |d_i| per joint, rad/s (a URDF robot: one value for every joint, one per joint, or none for
 *   the URDF's `<limit velocity>`)
 * @param maxAcceleration
 *   declared max |dd_i| per joint, rad/s^2 (a URDF robot: one value for every joint, or one per joint)
 * @param source
 *   `planar3` (the built-in planar arm above) or the path of a URDF file
 * @param tip
 *   the URDF link that ends the chain (empty: the only leaf)
 * @param allowMassless
 *   accept a URDF whose last joints move no mass (their torque identically zero), with a warning; refused
 *   otherwise (see [[Urdf]])
 * @param mounting
 *   the base's orientation in the world (`robot.base-rpy`): rotates the chain's gravity (see [[Mounting]])
 */
final case class RobotParams(
    m3: Double = 10.0,
    l1: Double = 0.4,
    l2: Double = 0.35,
    l3: Double = 0.3,
    g: Double = 9.81,
    maxVelocity: Seq[Double] = Seq(3.0, 3.0, 3.0),
    maxAcceleration: Seq[Double] = Seq(10.0, 10.0, 10.0),
    source: String = RobotParams.planar3,
    tip: String = "",
    allowMassless: Boolean = false,
    mounting: Mounting = Mounting.floor
) {

  private def finite(x: Double) = !x.isNaN && !x.isInfinite
  require(finite(m3) && m3 > 0 && m3 <= 1e4, s"robot.m3 must be a mass in (0, 10000] kg, got $m3")
  Seq("l1" -> l1, "l2" -> l2, "l3" -> l3).foreach { case (name, l) =>
    require(finite(l) && l > 0 && l <= 100, s"robot.$name must be a length in (0, 100] m, got $l")
  }
  require(finite(g) && g >= 0 && g <= 100, s"robot.g must be in [0, 100] m/s^2, got $g")
  require(source.nonEmpty, "robot.source must be planar3 or the path of a URDF file")
  if (isPlanar3) {
    require(
      maxVelocity.size == 3,
      s"robot.max-velocity needs 3 numbers (one per joint of planar3), got ${maxVelocity.size}"
    )
    require(
      maxAcceleration.size == 3,
      s"robot.max-acceleration needs 3 numbers (one per joint of planar3), got ${maxAcceleration.size}"
    )
    require(tip.isEmpty, s"robot.tip names a URDF link; the built-in planar3 has none (got '$tip')")
  } else
    require(
      maxAcceleration.nonEmpty,
      s"robot.max-acceleration must be declared for $source (a URDF gives no acceleration limits)"
    )
  RobotParams.checkRanges(maxVelocity, maxAcceleration)

  def isPlanar3: Boolean = source == RobotParams.planar3

  /**
   * The serial chain: the built-in planar arm, or the URDF file's chain to its tip (read on each call), on
   * the base's mounting.
   */
  def chain: SerialChain =
    (if (isPlanar3) Planar3.chain(this)
     else Urdf.read(java.nio.file.Paths.get(source), Option(tip).filter(_.nonEmpty), allowMassless))
      .mounted(mounting)

  /** Products of robot constants, folded at elaboration (the joint-3 closed form's coefficients). */
  val a: Double = m3 * l1 * l3 // multiplies dd1 cos(t2+t3) and d1^2 sin(t2+t3)
  val b: Double = m3 * l2 * l3 // multiplies (dd1+dd2) cos t3 and (d1+d2)^2 sin t3
  val c: Double = m3 * l3 * l3 // multiplies dd1+dd2+dd3
  val d: Double = m3 * g * l3 // multiplies sin(t1+t2+t3)
}

object RobotParams {

  /**
   * The declared ranges' own limits, one rule wherever ranges are given (here and in the graph's numerics):
   * finite and positive, with the upper limits every format derivation assumes.
   */
  def checkRanges(maxVelocity: Seq[Double], maxAcceleration: Seq[Double]): Unit = {
    def finite(x: Double) = !x.isNaN && !x.isInfinite
    maxVelocity.zipWithIndex.foreach { case (v, j) =>
      require(
        finite(v) && v > 0 && v <= 1000,
        s"robot.max-velocity of joint ${j + 1} must be in (0, 1000] rad/s, got $v"
      )
    }
    maxAcceleration.zipWithIndex.foreach { case (a, j) =>
      require(
        finite(a) && a > 0 && a <= 1e5,
        s"robot.max-acceleration of joint ${j + 1} must be in (0, 100000] rad/s^2, got $a"
      )
    }
  }
  val planar3: String = "planar3"
}
