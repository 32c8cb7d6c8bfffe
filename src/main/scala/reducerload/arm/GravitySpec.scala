package reducerload.arm

import reducerload.graph.{Interval, Signal}
import reducerload.robot.Vec3

/**
 * The run-time gravity a design serves (arms on moving platforms): its three components in base coordinates
 * are graph inputs ([[Signal.Gravity]]), the same mechanism as the payload's parameters, each within
 * [-maxMagnitude, maxMagnitude], so the range and error analysis covers every gravity vector of at most that
 * magnitude. The chain's gravity (folded with the mounting) is the reset value.
 *
 * @param maxMagnitude
 *   the declared bound on the gravity's magnitude, m/s^2
 */
final case class GravitySpec(maxMagnitude: Double) {
  require(maxMagnitude > 0, s"GravitySpec: no declared bound in $this")

  /** Each component's declared interval. */
  def range: Interval = Interval.symmetric(maxMagnitude)

  /** Every component's signal with its declared interval. */
  def ranges: Map[Signal.Parameter, Interval] = Signal.gravity.map(s => s -> range).toMap

  /** A gravity vector's components, by signal (m/s^2). */
  def values(g: Vec3): Map[Signal.Parameter, Double] = Signal.gravity.map(s => s -> g.toSeq(s.axis)).toMap
}
