package reducerload.graph

import reducerload.dynamics.{Num, V3, VectorAlgebra}
import reducerload.robot.{Mat3, Vec3}

import scala.collection.mutable

/** A graph node and a bound on the magnitude of its exact value over the declared input ranges. */
final case class Tracked(node: NodeId, bound: Double)

/**
 * Builds graph nodes (through `builder`) and proves magnitude bounds beside them: scalars by the triangle
 * inequality and |ab| <= |a| |b|, vectors by their length, which rotations keep and cross and dot products
 * multiply. Every bound proved for a node is recorded; the tightest is its hint. Used once, while one
 * computation runs.
 */
final class TrackingAlgebra(builder: GraphBuilder)
    extends VectorAlgebra[Tracked]()(TrackingAlgebra.num(builder)) {
  private val best = mutable.HashMap.empty[NodeId, Double]

  private def record(t: Tracked): Tracked = {
    val b = best.get(t.node).fold(t.bound)(math.min(_, t.bound))
    best(t.node) = b
    Tracked(t.node, b)
  }

  /** Inputs and sin/cos enter with their declared ranges. */
  def leaf(node: NodeId, bound: Double): Tracked = record(Tracked(node, bound))

  private def length(v: V3[Tracked]): Double = math.sqrt(v.toSeq.map(c => c.bound * c.bound).sum)
  private def capped(v: V3[Tracked], length: Double): V3[Tracked] = {
    val Seq(x, y, z) = v.toSeq.map(c => record(Tracked(c.node, math.min(c.bound, length))))
    V3(x, y, z)
  }

  override def rotate(axis: Vec3, cos: Tracked, sin: Tracked, v: V3[Tracked], inverse: Boolean): V3[Tracked] =
    capped(super.rotate(axis, cos, sin, v, inverse), length(v))
  override def cross(a: V3[Tracked], b: V3[Tracked]): V3[Tracked] =
    capped(super.cross(a, b), length(a) * length(b))
  override def dot(a: V3[Tracked], b: V3[Tracked]): Tracked = {
    val d = super.dot(a, b)
    record(Tracked(d.node, math.min(d.bound, length(a) * length(b))))
  }
  override def mul(m: Mat3, v: V3[Tracked]): V3[Tracked] = {
    val frobenius = math.sqrt(m.rows.flatten.map(x => x * x).sum) // >= the spectral norm
    capped(super.mul(m, v), frobenius * length(v))
  }
  override def plus(a: V3[Tracked], b: V3[Tracked]): V3[Tracked] =
    capped(super.plus(a, b), length(a) + length(b))

  def hints: Map[NodeId, Double] = best.toMap
}

object TrackingAlgebra {
  private def num(b: GraphBuilder): Num[Tracked] = new Num[Tracked] {
    def const(x: Double): Tracked = Tracked(b.const(x), math.abs(x))
    def plus(x: Tracked, y: Tracked): Tracked = Tracked(b.plus(x.node, y.node), x.bound + y.bound)
    def minus(x: Tracked, y: Tracked): Tracked = Tracked(b.minus(x.node, y.node), x.bound + y.bound)
    def times(x: Tracked, y: Tracked): Tracked = Tracked(b.times(x.node, y.node), x.bound * y.bound)
    def negate(x: Tracked): Tracked = Tracked(b.negate(x.node), x.bound)
  }
}
