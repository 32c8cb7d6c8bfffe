package reducerload.dynamics

import reducerload.robot.{JointKind, Mat3, SerialChain}

/** What one joint contributes per sample: cos and sin of its angle, its velocity and acceleration. */
final case class JointState[T](cos: T, sin: T, velocity: T, acceleration: T)

/** Cosine and sine of one angle (a sum of joint angles). */
final case class CosSin[T](cos: T, sin: T)

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
   * given, replaces the chain's constant gravity (base coordinates; run-time values of T). `summed`, when
   * given, gives cos and sin of a sum of consecutive joints' angles: each run of parallel axes
   * ([[parallelRuns]]) is then crossed in one rotation, from the motion before it to each of its joints and
   * from the wrench after it to each joint before, which takes multiply levels off both passes for a few more
   * products (docs/design.md, "Parallel axes").
   */
  def torques[T](
      chain: SerialChain,
      state: IndexedSeq[JointState[T]],
      added: Map[Int, BodyInertia[T]] = Map.empty[Int, BodyInertia[T]],
      gravity: Option[V3[T]] = None,
      summed: Option[Range => CosSin[T]] = None
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
    // With `summed`, each run of parallel axes is crossed in one rotation by its summed angle; else every joint
    // is a run of its own.
    val runs = summed.fold(joints.indices.map(j => j to j: Range))(_ => parallelRuns(chain))
    val runOf = joints.indices.map(j => runs.find(_.contains(j)).get)
    def cosSin(span: Range): CosSin[T] =
      if (span.size == 1) CosSin(state(span.head).cos, state(span.head).sin) else summed.get(span)
    // Joints `span` of one run, parent of the first -> the last's coordinates, and back: their fixed rotations,
    // then one rotation by the summed angle (each fixed rotation carries its joint's axis onto its parent's, so
    // the joint rotations commute past it onto the last axis).
    def fixed(span: Range): Mat3 = span.map(joints(_).origin.rotation).reduce(_ * _)
    def toChild(span: Range, v: V3[T]): V3[T] = {
      val cs = cosSin(span)
      va.rotate(joints(span.last).axis, cs.cos, cs.sin, va.mul(fixed(span).transpose, v), inverse = true)
    }
    def toParent(span: Range, v: V3[T]): V3[T] = {
      val cs = cosSin(span)
      va.mul(fixed(span), va.rotate(joints(span.last).axis, cs.cos, cs.sin, v, inverse = false))
    }
    def offset(j: Int): V3[T] = va.const(joints(j).origin.translation)

    // Forward pass: angular velocity w, angular acceleration dw, linear acceleration dv of each joint origin,
    // from the motion before the joint's run (along a run of parallel axes, w and dw add as about one joint).
    final case class Motion(w: V3[T], dw: V3[T], dv: V3[T])
    val baseAcceleration = gravity.fold(va.const(chain.gravity * -1.0))(g => V3(-g.x, -g.y, -g.z))
    val base = Motion(V3.zero[T], V3.zero[T], baseAcceleration)
    val motions = joints.indices.foldLeft(Vector.empty[Motion]) { (done, i) =>
      val span = runOf(i).head to i
      def before(l: Int) = if (l == 0) base else done(l - 1)
      val parent = before(span.head)
      val offsets = span.map(offset)
      val spin = va.scale(axes(i), span.map(state(_).velocity).reduce(n.plus))
      val wIn = toChild(span, parent.w)
      val w = va.plus(wIn, spin)
      val dw = va.plus(
        va.plus(toChild(span, parent.dw), va.cross(wIn, spin)),
        va.scale(axes(i), span.map(state(_).acceleration).reduce(n.plus))
      )
      // What each joint's offset adds to the acceleration before it (the run's first: the parent's too).
      val dv = span.zip(offsets).map { case (l, p) =>
        val m = before(l)
        val start = if (l == span.head) m.dv else V3.zero[T]
        toChild(l to i, va.plus(va.plus(start, va.cross(m.dw, p)), va.cross(m.w, va.cross(m.w, p))))
      }
      done :+ Motion(w, dw, dv.reduce(va.plus))
    }

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

    // Backward pass: what joint j carries is its body's wrench plus the bodies of joints j+1 to the end of
    // j+1's run (the last with all it carries), each moved to j's origin across the joints between.
    // A wrench moved: its force and moment turned into j's coordinates, and the lever r from j's origin to the
    // force's (the force's moment about j is r x f).
    final case class Moved(f: V3[T], m: V3[T], r: V3[T])
    def moved(j: Int, l: Int, w: Wrench): Moved = {
      val span = j + 1 to l
      val f = toParent(span, w.f)
      val m = toParent(span, w.m)
      // Joint l's origin from joint j's, in j's coordinates.
      val r = span
        .map(x => if (x == span.head) offset(x) else toParent(span.head until x, offset(x)))
        .reduce(va.plus)
      Moved(f, m, r)
    }
    val carried = joints.indices.reverse.foldLeft(Map.empty[Int, Wrench]) { (done, j) =>
      val total =
        if (j == joints.size - 1) own(j)
        else {
          val last = runOf(j + 1).last
          val parts = (j + 1 to last).map(l => moved(j, l, if (l == last) done(last) else own(l)))
          val f = (own(j).f +: parts.map(_.f)).reduce(va.plus)
          val m = (own(j).m +: parts.map(_.m)).reduce(va.plus)
          Wrench(f, (m +: parts.map(p => va.cross(p.r, p.f))).reduce(va.plus))
        }
      done + (j -> total)
    }
    joints.indices.map(j => va.dot(axes(j), carried(j).m))
  }

  /**
   * The chain cut into runs of consecutive joints with parallel axes (each joint's fixed rotation carries its
   * axis onto its parent's, same sense): along a run the joint rotations commute, so a run is crossed in one
   * rotation by the summed angle. A joint of its own is a run of one.
   */
  def parallelRuns(chain: SerialChain): IndexedSeq[Range] = {
    val joints = chain.joints
    def parallel(j: Int) = (joints(j).origin.rotation * joints(j).axis - joints(j - 1).axis).norm < 1e-9
    joints.indices.foldLeft(Vector.empty[Range]) { (runs, j) =>
      if (j > 0 && parallel(j)) runs.init :+ (runs.last.head to j) else runs :+ (j to j)
    }
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
