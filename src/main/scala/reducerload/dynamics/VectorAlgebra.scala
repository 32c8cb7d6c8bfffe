package reducerload.dynamics

import reducerload.robot.{Mat3, Vec3}

/**
 * The vector operations [[Rnea]] is written in. The default derives them from a [[Num]]; an analysis may
 * override them to carry facts only vectors have (a rotation keeps the length, |a x b| <= |a| |b|) that the
 * scalar operations cannot see.
 */
class VectorAlgebra[T](implicit val num: Num[T]) {
  def const(v: Vec3): V3[T] = V3.const[T](v)
  def plus(a: V3[T], b: V3[T]): V3[T] = V3.plus(a, b)
  def scale(a: V3[T], k: T): V3[T] = V3.scale(a, k)
  def cross(a: V3[T], b: V3[T]): V3[T] = V3.cross(a, b)
  def dot(a: V3[T], b: V3[T]): T = V3.dot(a, b)

  /** A constant matrix times a vector: only non-zero entries cost arithmetic once folded. */
  def mul(m: Mat3, v: V3[T]): V3[T] = V3.mul(m, v)

  /**
   * Rotation by the angle with `cos`, `sin` about the unit `axis` (or its inverse), applied to `v`: Rq v = c
   * (v - a (a.v)) + s (a x v) + a (a.v); with a constant axis the zeros fold away.
   */
  def rotate(axis: Vec3, cos: T, sin: T, v: V3[T], inverse: Boolean): V3[T] = {
    val a = const(axis)
    val along = V3.scale(a, V3.dot(a, v))
    val across = V3(num.minus(v.x, along.x), num.minus(v.y, along.y), num.minus(v.z, along.z))
    val turn = if (inverse) V3.cross(v, a) else V3.cross(a, v)
    V3.plus(V3.plus(V3.scale(across, cos), V3.scale(turn, sin)), along)
  }
}

object VectorAlgebra {
  implicit def fromNum[T](implicit n: Num[T]): VectorAlgebra[T] = new VectorAlgebra[T]
}
