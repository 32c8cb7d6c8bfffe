package reducerload.sim.model

import reducerload.dynamics.{JointState, Num, Rnea, VectorAlgebra}
import reducerload.graph.{AngleSum, TrigFn}
import reducerload.load.{Joint3Load, LoadModel}
import reducerload.robot.RobotParams
import reducerload.robot.SerialChain

import scala.collection.mutable

/**
 * A replay's double-precision reference ([[Rnea.reference]], or the joint-3 closed form of
 * `LoadReference.torque`) as a [[DoubleTape]], with its inputs read from a trajectory row (n angles, n
 * velocities, n accelerations): bit-identical to the reference (ReplayArraysSpec), without its per-sample
 * collections.
 */
final class ReferenceTape private (
    val tape: DoubleTape,
    joints: Int,
    source: Array[Int],
    joint: Array[Int],
    sumJoints: Array[Array[Int]],
    sumMultiples: Array[Array[Double]],
    seeded: Array[Boolean]
) {
  import ReferenceTape._

  def outputs: Int = tape.outputSlots.length

  /** [[evaluate]] of a row on its own. */
  def evaluate(row: Array[Double], v: Array[Double]): Unit = evaluate(row, 0, v)

  /**
   * Fill `v` (from `tape.scratch()`) with the inputs of the row at `rows(at ..)` and run the tape; results by
   * `tape.output`.
   */
  def evaluate(rows: Array[Double], at: Int, v: Array[Double]): Unit = {
    val slots = tape.inputSlots
    val n = joints
    var k = 0
    while (k < slots.length) {
      val j = joint(k)
      v(slots(k)) = (source(k): @annotation.switch) match {
        case Velocity     => rows(at + n + j)
        case Acceleration => rows(at + 2 * n + j)
        case CosQ         => math.cos(rows(at + j))
        case SinQ         => math.sin(rows(at + j))
        case _            =>
          // AngleSum.radians: terms.map { case (j, k) => k * q(j) }.sum, whose seed 0.0 (when the
          // collection adds one) only turns a -0.0 into 0.0.
          val js = sumJoints(k)
          val ks = sumMultiples(k)
          var rad = ks(0) * rows(at + js(0))
          var t = 1
          while (t < js.length) { rad += ks(t) * rows(at + js(t)); t += 1 }
          if (seeded(k)) rad += 0.0
          if (source(k) == SinSum) math.sin(rad) else math.cos(rad)
      }
      k += 1
    }
    tape.run(v)
  }
}

object ReferenceTape {
  private final val Velocity = 0
  private final val Acceleration = 1
  private final val CosQ = 2
  private final val SinQ = 3
  private final val CosSum = 4
  private final val SinSum = 5

  private final class Inputs(make: () => Int) {
    val order = mutable.LinkedHashMap.empty[Any, Int] // descriptor -> slot
    def apply(key: Any): Int = order.getOrElseUpdate(key, make())
  }

  private def build(joints: Int, formula: (Num[Int], Inputs) => Seq[Int]): ReferenceTape = {
    var inputs: Inputs = null
    val tape = DoubleTape.record { (num, make) => inputs = new Inputs(make); formula(num, inputs) }
    val keys = inputs.order.keys.toArray
    require(
      keys.indices.forall(k => inputs.order(keys(k)) == tape.inputSlots(k)),
      "ReferenceTape: inputs out of order"
    )
    val source = keys.map {
      case ("qd", _)       => Velocity
      case ("qdd", _)      => Acceleration
      case ("cos", _: Int) => CosQ
      case ("sin", _: Int) => SinQ
      case (TrigFn.Cos, _) => CosSum
      case (TrigFn.Sin, _) => SinSum
      case other           => throw new IllegalStateException(s"ReferenceTape: unknown input $other")
    }
    val joint = keys.map {
      case (_, j: Int) => j
      case _           => -1
    }
    val sums = keys.map {
      case (_, a: AngleSum) => Some(a)
      case _                => None
    }
    val sumJoints = sums.map(_.fold(Array.empty[Int])(_.terms.map(_._1).toArray))
    val sumMultiples = sums.map(_.fold(Array.empty[Double])(_.terms.map(_._2.toDouble).toArray))
    // Whether radians() adds the terms to a seed 0.0: with every term -0.0 the sum is 0.0 then, -0.0 otherwise.
    val seeded = sums.map(_.exists { a =>
      require(
        a.terms.nonEmpty && a.terms.map(_._1).distinct.size == a.terms.size,
        s"ReferenceTape: angle sum $a"
      )
      val q = Array.fill(joints)(0.0)
      a.terms.foreach { case (j, k) => q(j) = if (k > 0) -0.0 else 0.0 }
      val r = a.radians(q.toIndexedSeq)
      require(r == 0.0, s"ReferenceTape: probe of $a gave $r")
      1.0 / r > 0
    })
    new ReferenceTape(tape, joints, source, joint, sumJoints, sumMultiples, seeded)
  }

  /**
   * [[Rnea.reference]] of `chain`: JointState(cos q, sin q, qd, qdd) per joint, the torque of every joint.
   */
  def rnea(chain: SerialChain): ReferenceTape = build(
    chain.size,
    { (num, in) =>
      val states = (0 until chain.size).map(j =>
        JointState(in(("cos", j)), in(("sin", j)), in(("qd", j)), in(("qdd", j)))
      )
      Rnea.torques(chain, states)(VectorAlgebra.fromNum(num))
    }
  )

  /** `LoadReference.torque` of the joint-3 closed form `model` (3 joints). */
  def joint3(robot: RobotParams, model: LoadModel): ReferenceTape = build(
    3,
    (num, in) =>
      Seq(
        Joint3Load.torque[Int](robot, model, (fn, a) => in((fn, a)), j => in(("qd", j)), j => in(("qdd", j)))(
          num
        )
      )
  )
}
