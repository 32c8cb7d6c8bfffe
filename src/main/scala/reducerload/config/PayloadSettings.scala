package reducerload.config

/**
 * The payload keys (`payload.*`) as written: with `enabled`, the payload's ten inertial parameters are
 * run-time inputs of the datapath within the declared set (see [[reducerload.arm.PayloadSpec]]), resolved
 * against the robot by the compiler. Only what needs no robot is checked here.
 *
 * @param maxMass
 *   heaviest payload, kg (no default: 0 until declared)
 * @param comRadius
 *   each coordinate of the centre of mass within this distance of the payload frame's origin, m
 * @param maxGyrationRadius
 *   every element of the inertia about the centre of mass within maxMass x this^2, m
 * @param frame
 *   the link the payload is stated in (empty: the tip)
 */
final case class PayloadSettings(
    enabled: Boolean = false,
    maxMass: Double = 0.0,
    comRadius: Double = 0.1,
    maxGyrationRadius: Double = 0.1,
    frame: String = ""
) {
  private def finite(x: Double) = !x.isNaN && !x.isInfinite
  require(
    finite(maxMass) && maxMass >= 0 && maxMass <= PayloadSettings.largestMass,
    s"payload.max-mass must be in [0, ${PayloadSettings.largestMass}] kg, got $maxMass"
  )
  require(
    !enabled || maxMass > 0,
    "payload.enabled = true needs payload.max-mass: the heaviest payload the design serves, kg"
  )
  Seq("com-radius" -> comRadius, "max-gyration-radius" -> maxGyrationRadius).foreach { case (key, r) =>
    require(
      finite(r) && r >= 0 && r <= PayloadSettings.largestRadius,
      s"payload.$key must be in [0, ${PayloadSettings.largestRadius}] m, got $r"
    )
  }
}

object PayloadSettings {

  /** Largest max-mass (kg) and radius (m) accepted: beyond any arm's payload, within the formats' reach. */
  val largestMass: Double = 1e4
  val largestRadius: Double = 10.0
}

/**
 * The gravity keys (`gravity.*`): with `runtime`, the gravity vector (base coordinates) is three run-time
 * inputs of the datapath, each within [-maxMagnitude, maxMagnitude], committed like the payload (arms on
 * moving platforms); its reset value is the elaboration gravity (the robot's, rotated by robot.base-rpy).
 *
 * @param maxMagnitude
 *   the declared bound on the gravity's magnitude, m/s^2 (each component within it)
 */
final case class GravitySettings(
    runtime: Boolean = false,
    maxMagnitude: Double = GravitySettings.defaultMax
) {
  require(
    !maxMagnitude.isNaN && maxMagnitude > 0 && maxMagnitude <= GravitySettings.largestMagnitude,
    s"gravity.max-magnitude must be in (0, ${GravitySettings.largestMagnitude}] m/s^2, got $maxMagnitude"
  )
}

object GravitySettings {

  /** 1.5 g: the standard gravity with the accelerations of a slowly moving platform. */
  val defaultMax: Double = 1.5 * 9.80665

  /** Largest max-magnitude accepted (m/s^2): beyond any platform, within the formats' reach. */
  val largestMagnitude: Double = 1e3
}
