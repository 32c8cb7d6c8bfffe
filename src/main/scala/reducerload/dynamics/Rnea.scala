package reducerload.dynamics

import reducerload.robot.{JointKind, Mat3, SerialChain}

/** What one joint contributes per sample: cos and sin of its angle, its velocity and acceleration. */
final case class JointState[T](cos: T, sin: T, velocity: T, acceleration: T)

/**
 * Inverse dynamics of a serial chain by the recursive Newton-Euler algorithm (Featherstone, *Rigid
 * Body Dynamics Algorithms*, ch. 5; Craig, ch. 6), in each joint's own frame, written once over any
 * [[Num]]. Robot constants enter through `Num.const`, so on graph nodes they fold: unit axes, zero
 * offsets and pi/2 twists cost no arithmetic. Gravity enters as an acceleration of the base.
 *
 * Each body's forces are taken about its joint's origin, with its first moment h = m c and its
 * inertia about the origin, which saves the centre-of-mass terms of the textbook form.
 */
object Rnea {
  import Num.NumOps

  def torques[T](chain: SerialChain, state: IndexedSeq[JointState[T]])(implicit n: Num[T]): IndexedSeq[T] = {
    require(state.size == chain.size, s"Rnea: ${state.size} joint states for ${chain.size} joints")
    chain.joints.foreach { j =>
      require(j.kind != JointKind.Prismatic, s"robot ${chain.name}: joint ${j.name}: prismatic joints are not supported by the dynamics compiler yet")
    }
    val joints = chain.joints
    val axes = joints.map(j => V3.const[T](j.axis))

    // Rotation of joint j at its angle, applied to a vector: Rq v = c (v - a (a.v)) + s (a x v) + a (a.v).
    def rotate(j: Int, v: V3[T], inverse: Boolean): V3[T] = {
      val a = axes(j)
      val along = V3.scale(a, V3.dot(a, v))
      val across = V3(v.x - along.x, v.y - along.y, v.z - along.z)
      val turn = if (inverse) V3.cross(v, a) else V3.cross(a, v)
      V3.plus(V3.plus(V3.scale(across, state(j).cos), V3.scale(turn, state(j).sin)), along)
    }
    // Parent coordinates -> joint j's coordinates, and back.
    def toChild(j: Int, v: V3[T]): V3[T] = rotate(j, V3.mul(joints(j).origin.rotation.transpose, v), inverse = true)
    def toParent(j: Int, v: V3[T]): V3[T] = V3.mul(joints(j).origin.rotation, rotate(j, v, inverse = false))

    // Forward pass: angular velocity w, angular acceleration dw, linear acceleration dv of each joint origin.
    final case class Motion(w: V3[T], dw: V3[T], dv: V3[T])
    val base = Motion(V3.zero[T], V3.zero[T], V3.const[T](chain.gravity * -1.0))
    val motions = joints.indices.scanLeft(base) { (parent, j) =>
      val p = V3.const[T](joints(j).origin.translation)
      val spin = V3.scale(axes(j), state(j).velocity)
      val wIn = toChild(j, parent.w)
      val w = V3.plus(wIn, spin)
      val dw = V3.plus(V3.plus(toChild(j, parent.dw), V3.cross(wIn, spin)), V3.scale(axes(j), state(j).acceleration))
      val dvParent = V3.plus(V3.plus(parent.dv, V3.cross(parent.dw, p)), V3.cross(parent.w, V3.cross(parent.w, p)))
      Motion(w, dw, toChild(j, dvParent))
    }.tail

    // Each body's inertial force and moment about its joint's origin.
    final case class Wrench(f: V3[T], m: V3[T])
    val own = joints.indices.map { j =>
      val body = joints(j).body
      val Motion(w, dw, dv) = motions(j)
      val h = V3.const[T](body.com * body.mass)
      val c = body.com
      val inertiaAtOrigin = body.inertia + (Mat3.identity.scale(c.dot(c)) - Mat3.tabulate((r, k) => c.toSeq(r) * c.toSeq(k))).scale(body.mass)
      val f = V3.plus(V3.plus(V3.scale(dv, n.const(body.mass)), V3.cross(dw, h)), V3.cross(w, V3.cross(w, h)))
      val m = V3.plus(V3.plus(V3.mul(inertiaAtOrigin, dw), V3.cross(w, V3.mul(inertiaAtOrigin, w))), V3.cross(h, dv))
      Wrench(f, m)
    }

    // Backward pass: what joint j carries is its body's wrench plus the child's, moved to j's origin.
    val carried = joints.indices.reverse.foldLeft(List.empty[Wrench]) { (acc, j) =>
      val total = acc.headOption match {
        case None => own(j)
        case Some(child) =>
          val fc = toParent(j + 1, child.f)
          val mc = toParent(j + 1, child.m)
          val p = V3.const[T](joints(j + 1).origin.translation)
          Wrench(V3.plus(own(j).f, fc), V3.plus(V3.plus(own(j).m, mc), V3.cross(p, fc)))
      }
      total :: acc
    }.toIndexedSeq
    joints.indices.map(j => V3.dot(axes(j), carried(j).m))
  }

  /** Double-precision reference: joint torques (N·m) at angles `q`, velocities `qd`, accelerations `qdd`. */
  def reference(chain: SerialChain, q: Seq[Double], qd: Seq[Double], qdd: Seq[Double]): IndexedSeq[Double] = {
    require(q.size == chain.size && qd.size == chain.size && qdd.size == chain.size,
      s"Rnea.reference: ${chain.size} joints need ${chain.size} angles, velocities and accelerations")
    torques(chain, chain.joints.indices.map(j => JointState(math.cos(q(j)), math.sin(q(j)), qd(j), qdd(j))))
  }
}
