package reducerload.dynamics

import reducerload.robot.{JointKind, SerialChain}

/** What one joint contributes per sample: cos and sin of its angle, its velocity and acceleration. */
final case class JointState[T](cos: T, sin: T, velocity: T, acceleration: T)

/**
 * Inverse dynamics of a serial chain by the recursive Newton-Euler algorithm (Featherstone, *Rigid Body
 * Dynamics Algorithms*, ch. 5; Craig, ch. 6), in each joint's own frame, written once over any [[Num]]. Robot
 * constants enter through `Num.const`, so on graph nodes they fold: unit axes, zero offsets and pi/2 twists
 * cost no arithmetic. Gravity enters as an acceleration of the base.
 *
 * Each body's forces are taken about its joint's origin, with its first moment h = m c and its inertia about
 * the origin, which saves the centre-of-mass terms of the textbook form.
 */
object Rnea {
  import Num.NumOps

  /**
   * Joint torques for `state`; `added` gives joints a body beyond their constant one (a payload, whose
   * parameters may be run-time values of T): that joint's body is the constant one plus it. `gravity`, when
   * given, replaces the chain's constant gravity (base coordinates; run-time values of T).
   */
  def torques[T](
      chain: SerialChain,
      state: IndexedSeq[JointState[T]],
      added: Map[Int, BodyInertia[T]] = Map.empty[Int, BodyInertia[T]],
      gravity: Option[V3[T]] = None
  )(implicit
      va: VectorAlgebra[T]
  ): IndexedSeq[T] = {
    implicit val n: Num[T] = va.num
    require(state.size == chain.size, s"Rnea: ${state.size} joint states for ${chain.size} joints")
    chain.joints.foreach { j =>
      require(
        j.kind != JointKind.Prismatic,
        s"${chain.label}: joint '${j.name}': prismatic joints are not " +
          s"supported by the dynamics compiler yet"
      )
    }
    val joints = chain.joints
    val axes = joints.map(j => va.const(j.axis))
    def rotate(j: Int, v: V3[T], inverse: Boolean) =
      va.rotate(joints(j).axis, state(j).cos, state(j).sin, v, inverse)
    // Parent coordinates -> joint j's coordinates, and back.
    def toChild(j: Int, v: V3[T]): V3[T] =
      rotate(j, va.mul(joints(j).origin.rotation.transpose, v), inverse = true)
    def toParent(j: Int, v: V3[T]): V3[T] = va.mul(joints(j).origin.rotation, rotate(j, v, inverse = false))

    // Forward pass: angular velocity w, angular acceleration dw, linear acceleration dv of each joint origin.
    final case class Motion(w: V3[T], dw: V3[T], dv: V3[T])
    val baseAcceleration = gravity.fold(va.const(chain.gravity * -1.0))(g => V3(-g.x, -g.y, -g.z))
    val base = Motion(V3.zero[T], V3.zero[T], baseAcceleration)
    val motions = joints.indices
      .scanLeft(base) { (parent, j) =>
        val p = va.const(joints(j).origin.translation)
        val spin = va.scale(axes(j), state(j).velocity)
        val wIn = toChild(j, parent.w)
        val w = va.plus(wIn, spin)
        val dw = va.plus(
          va.plus(toChild(j, parent.dw), va.cross(wIn, spin)),
          va.scale(axes(j), state(j).acceleration)
        )
        val dvParent =
          va.plus(va.plus(parent.dv, va.cross(parent.dw, p)), va.cross(parent.w, va.cross(parent.w, p)))
        Motion(w, dw, toChild(j, dvParent))
      }
      .tail

    // Each body's inertial force and moment about its joint's origin.
    final case class Wrench(f: V3[T], m: V3[T])
    // A body with run-time parameters: the same wrench, its matrix products over T.
    def wrenchOf(b: BodyInertia[T], motion: Motion): Wrench = {
      val Motion(w, dw, dv) = motion
      val f = va.plus(va.plus(va.scale(dv, b.mass), va.cross(dw, b.h)), va.cross(w, va.cross(w, b.h)))
      val m = va.plus(
        va.plus(Sym3.times(b.inertia, dw), va.cross(w, Sym3.times(b.inertia, w))),
        va.cross(b.h, dv)
      )
      Wrench(f, m)
    }
    // A constant body: its parameters fold into constant multiplies.
    def constantWrench(j: Int): Wrench = {
      val body = joints(j).body
      val Motion(w, dw, dv) = motions(j)
      val h = va.const(body.com * body.mass)
      val inertiaAtOrigin = BodyInertia.inertiaAtOrigin(body)
      val f = va.plus(va.plus(va.scale(dv, n.const(body.mass)), va.cross(dw, h)), va.cross(w, va.cross(w, h)))
      val m = va.plus(
        va.plus(va.mul(inertiaAtOrigin, dw), va.cross(w, va.mul(inertiaAtOrigin, w))),
        va.cross(h, dv)
      )
      Wrench(f, m)
    }

    val own = joints.indices.map { j =>
      added.get(j) match {
        case Some(extra) =>
          wrenchOf(BodyInertia.plus(BodyInertia.constant[T](joints(j).body), extra), motions(j))
        case None => constantWrench(j)
      }
    }

    // Backward pass: what joint j carries is its body's wrench plus the child's, moved to j's origin.
    val carried = joints.indices.reverse
      .foldLeft(List.empty[Wrench]) { (acc, j) =>
        val total = acc.headOption match {
          case None => own(j)
          case Some(child) =>
            val fc = toParent(j + 1, child.f)
            val mc = toParent(j + 1, child.m)
            val p = va.const(joints(j + 1).origin.translation)
            Wrench(va.plus(own(j).f, fc), va.plus(va.plus(own(j).m, mc), va.cross(p, fc)))
        }
        total :: acc
      }
      .toIndexedSeq
    joints.indices.map(j => va.dot(axes(j), carried(j).m))
  }

  /**
   * Double-precision reference: joint torques (N·m) at angles `q`, velocities `qd`, accelerations `qdd`, with
   * the bodies `added` to joints' own (see [[torques]]).
   */
  def reference(
      chain: SerialChain,
      q: Seq[Double],
      qd: Seq[Double],
      qdd: Seq[Double],
      added: Map[Int, BodyInertia[Double]] = Map.empty
  ): IndexedSeq[Double] = {
    require(
      q.size == chain.size && qd.size == chain.size && qdd.size == chain.size,
      s"Rnea.reference: ${chain.size} joints need ${chain.size} angles, velocities and accelerations"
    )
    torques(
      chain,
      chain.joints.indices.map(j => JointState(math.cos(q(j)), math.sin(q(j)), qd(j), qdd(j))),
      added
    )
  }
}
