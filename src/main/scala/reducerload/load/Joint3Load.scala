package reducerload.load

import reducerload.dynamics.Num
import reducerload.dynamics.Num.NumOps
import reducerload.graph.{AngleSum, TrigFn}
import reducerload.robot.RobotParams

/**
 * The planar arm's joint-3 load in closed form (tau3 of docs/equations.md, or the paper's equation (6) with
 * weight 2 on dd2), written once over [[Num]]: on doubles it is the reference
 * ([[reducerload.arm.LoadReference]]), on graph nodes the datapath ([[reducerload.arm.Dynamics.Joint3]]).
 *
 * A dd1 c23 + B (dd1 + k dd2) c3 + A d1^2 s23 + B (d1+d2)^2 s3 + C (dd1+dd2+dd3) + D s123
 *
 * Angle sums stay sums of binary angles (t2+t3, t1+t2+t3), one sin/cos each, as in the paper.
 */
object Joint3Load {

  /**
   * The joint-3 torque; `trig` gives sin/cos of an angle sum (joints 0-based), `qd` / `qdd` a joint's
   * velocity / acceleration.
   */
  def torque[T](r: RobotParams, model: LoadModel, trig: (TrigFn, AngleSum) => T, qd: Int => T, qdd: Int => T)(
      implicit n: Num[T]
  ): T = {
    require(model.closedForm, s"model ${model.name} is not a joint-3 closed form")
    val (t3, t23, t123) = (AngleSum.of(2), AngleSum.of(1, 2), AngleSum.of(0, 1, 2))
    val (a, b, c, d) = (n.const(r.a), n.const(r.b), n.const(r.c), n.const(r.d))
    val a12 = qdd(0) + qdd(1)
    // The paper's weight 2 on dd2 as one more addition of dd2 (exact, no multiplier), sharing dd1 + dd2.
    val weighted = (1 until model.dd2Weight).foldLeft(a12)((sum, _) => sum + qdd(1))
    val v12 = qd(0) + qd(1)
    val p1 = a * qdd(0) * trig(TrigFn.Cos, t23)
    val p2 = b * weighted * trig(TrigFn.Cos, t3)
    val p3 = a * (qd(0) * qd(0)) * trig(TrigFn.Sin, t23)
    val p4 = b * (v12 * v12) * trig(TrigFn.Sin, t3)
    val p5 = c * (a12 + qdd(2))
    val p6 = d * trig(TrigFn.Sin, t123)
    ((p1 + p2) + (p3 + p4)) + (p6 + p5)
  }
}
