package reducerload.arm

import reducerload.load.{Joint3Load, LoadModel}
import reducerload.robot.RobotParams

/** Double-precision reference of both closed forms: [[Joint3Load]] on doubles. */
object LoadReference {
  def torque(r: RobotParams, model: LoadModel, s: ArmSample): Double =
    Joint3Load.torque[Double](
      r,
      model,
      (fn, a) => reducerload.graph.TrigFn.reference(fn, a.radians(s.q)),
      s.qd,
      s.qdd
    )
}
