package reducerload.dynamics

import reducerload.robot.{Mat3, RigidBody, Transform}

/** A symmetric 3x3 matrix of any [[Num]], by its upper triangle. */
final case class Sym3[T](xx: T, xy: T, xz: T, yy: T, yz: T, zz: T) {
  def apply(i: Int, j: Int): T = (math.min(i, j), math.max(i, j)) match {
    case (0, 0) => xx
    case (0, 1) => xy
    case (0, 2) => xz
    case (1, 1) => yy
    case (1, 2) => yz
    case _      => zz
  }
}

object Sym3 {
  import Num.NumOps

  def tabulate[T](f: (Int, Int) => T): Sym3[T] = Sym3(f(0, 0), f(0, 1), f(0, 2), f(1, 1), f(1, 2), f(2, 2))
  def const[T](m: Mat3)(implicit n: Num[T]): Sym3[T] = tabulate((i, j) => n.const(m(i, j)))
  def plus[T: Num](a: Sym3[T], b: Sym3[T]): Sym3[T] = tabulate((i, j) => a(i, j) + b(i, j))

  /** m v, each row summed in the order x, y, z. */
  def times[T](m: Sym3[T], v: V3[T])(implicit n: Num[T]): V3[T] = {
    def row(i: Int) = v.toSeq.zipWithIndex.map { case (e, j) => m(i, j) * e }.reduce(n.plus)
    V3(row(0), row(1), row(2))
  }

  /**
   * R S R^T for a constant rotation R: each element a sum of constant multiples of S's six elements, the two
   * products of an off-diagonal element merged; zeros fold away (R = identity costs nothing).
   */
  def rotated[T](r: Mat3, s: Sym3[T])(implicit n: Num[T]): Sym3[T] = tabulate { (i, j) =>
    val terms = for (k <- 0 until 3; l <- k until 3) yield {
      val k2 = if (k == l) r(i, k) * r(j, l) else r(i, k) * r(j, l) + r(i, l) * r(j, k)
      n.const(k2) * s(k, l)
    }
    terms.reduce(n.plus)
  }
}

/**
 * A rigid body's inertial parameters as RNEA uses them, about its joint's origin in the joint's frame: the
 * mass, the first moment h = m c and the inertia about the origin. Linear in the body, so bodies fixed to one
 * joint add; over graph nodes the parameters may be run-time inputs (a payload, identified parameters).
 */
final case class BodyInertia[T](mass: T, h: V3[T], inertia: Sym3[T])

object BodyInertia {
  import Num.NumOps

  def plus[T: Num](a: BodyInertia[T], b: BodyInertia[T]): BodyInertia[T] =
    BodyInertia(a.mass + b.mass, V3.plus(a.h, b.h), Sym3.plus(a.inertia, b.inertia))

  /** A body's inertia about its frame's origin: the parallel-axis theorem, I + m (|c|^2 E - c c^T). */
  def inertiaAtOrigin(body: RigidBody): Mat3 = {
    val c = body.com
    body.inertia + (Mat3.identity.scale(c.dot(c)) - Mat3.tabulate((r, k) => c.toSeq(r) * c.toSeq(k)))
      .scale(body.mass)
  }

  /** A constant body (folded at elaboration). */
  def constant[T](body: RigidBody)(implicit n: Num[T]): BodyInertia[T] =
    BodyInertia(n.const(body.mass), V3.const[T](body.com * body.mass), Sym3.const[T](inertiaAtOrigin(body)))

  /**
   * A body given as robot controllers state load data, in a frame fixed to the joint at `frame` (its pose in
   * the joint's frame): mass m, centre of mass c and inertia Ic about the centre of mass, both in that frame.
   * With d = p + R c: h = m d, and I = R Ic R^T + m (|d|^2 E - d d^T), whose products m d_i d_j are h_i d_j
   * (six of them, by symmetry).
   */
  def placed[T](frame: Transform, mass: T, com: V3[T], inertia: Sym3[T])(implicit
      va: VectorAlgebra[T]
  ): BodyInertia[T] = {
    implicit val n: Num[T] = va.num
    val d = va.plus(va.mul(frame.rotation, com), va.const(frame.translation))
    val h = va.scale(d, mass)
    val hd = Sym3.tabulate((i, j) => h.toSeq(i) * d.toSeq(j))
    val shift = Sym3.tabulate((i, j) =>
      if (i != j) -hd(i, j)
      else {
        val Seq(a, b) = (0 until 3).filter(_ != i)
        hd(a, a) + hd(b, b)
      }
    )
    BodyInertia(mass, h, Sym3.plus(Sym3.rotated(frame.rotation, inertia), shift))
  }

  /** The same body as [[placed]] in doubles. */
  def placed(frame: Transform, body: RigidBody): BodyInertia[Double] = placed[Double](
    frame,
    body.mass,
    V3.const[Double](body.com),
    Sym3.const[Double](body.inertia)
  )
}
