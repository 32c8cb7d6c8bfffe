package reducerload.dynamics

/**
 * The arithmetic the dynamics are written in. [[Rnea]] is written once against it and instantiated twice: on
 * doubles (the reference) and on expression-graph nodes ([[GraphBuilder]]), from which the bit-accurate
 * model, the analyses and the hardware are all read.
 */
trait Num[T] {
  def const(x: Double): T
  def plus(a: T, b: T): T
  def minus(a: T, b: T): T
  def times(a: T, b: T): T
  def negate(a: T): T
  final def zero: T = const(0.0)
}

object Num {
  implicit val doubleNum: Num[Double] = new Num[Double] {
    def const(x: Double): Double = x
    def plus(a: Double, b: Double): Double = a + b
    def minus(a: Double, b: Double): Double = a - b
    def times(a: Double, b: Double): Double = a * b
    def negate(a: Double): Double = -a
  }

  /** Infix operators for any `Num`. */
  implicit final class NumOps[T](private val a: T)(implicit n: Num[T]) {
    def +(b: T): T = n.plus(a, b)
    def -(b: T): T = n.minus(a, b)
    def *(b: T): T = n.times(a, b)
    def unary_- : T = n.negate(a)
  }
}

/** A 3-vector of any [[Num]]. */
final case class V3[T](x: T, y: T, z: T) {
  def toSeq: Seq[T] = Seq(x, y, z)
}

object V3 {
  import Num.NumOps
  def const[T](v: reducerload.robot.Vec3)(implicit n: Num[T]): V3[T] =
    V3(n.const(v.x), n.const(v.y), n.const(v.z))
  def zero[T](implicit n: Num[T]): V3[T] = V3(n.zero, n.zero, n.zero)
  def plus[T: Num](a: V3[T], b: V3[T]): V3[T] = V3(a.x + b.x, a.y + b.y, a.z + b.z)
  def scale[T: Num](a: V3[T], k: T): V3[T] = V3(a.x * k, a.y * k, a.z * k)
  def cross[T: Num](a: V3[T], b: V3[T]): V3[T] =
    V3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x)
  def dot[T: Num](a: V3[T], b: V3[T]): T = a.x * b.x + a.y * b.y + a.z * b.z

  /** A constant matrix times a vector: only the non-zero entries cost arithmetic once folded. */
  def mul[T](m: reducerload.robot.Mat3, v: V3[T])(implicit n: Num[T]): V3[T] = {
    def row(i: Int) =
      Seq(v.x, v.y, v.z).zipWithIndex.map { case (e, j) => n.times(n.const(m(i, j)), e) }.reduce(n.plus)
    V3(row(0), row(1), row(2))
  }
}
