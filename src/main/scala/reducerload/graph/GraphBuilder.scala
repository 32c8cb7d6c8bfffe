package reducerload.graph

import reducerload.dynamics.Num

import scala.collection.mutable

/**
 * Builds a [[Graph]] while a computation written over [[Num]] runs on it: every operation is folded
 * (constants combined, zeros and ones removed, constant factors merged, negations pushed into constants and
 * subtractions) and hash-consed, so equal subexpressions are one node. A builder is used once, inside
 * [[GraphBuilder.build]].
 */
final class GraphBuilder private () extends Num[NodeId] {
  import Op._

  private val nodes = mutable.ArrayBuffer.empty[Op]
  private val index = mutable.HashMap.empty[Op, NodeId]

  private def node(op: Op): NodeId = index.getOrElseUpdate(op, { nodes += op; NodeId(nodes.size - 1) })
  private def constOf(id: NodeId): Option[Double] = nodes(id.index) match {
    case Const(v) => Some(v)
    case _        => None
  }
  private def negOf(id: NodeId): Option[NodeId] = nodes(id.index) match {
    case Neg(x) => Some(x)
    case _      => None
  }
  private def ordered(a: NodeId, b: NodeId): (NodeId, NodeId) = if (a.index <= b.index) (a, b) else (b, a)

  def input(s: Signal): NodeId = node(Input(s))
  def trig(fn: TrigFn, angle: AngleSum): NodeId = node(Trig(fn, angle))

  /** Constants this small (SI units) are zero: far below any LSB, and they would cost a multiplier. */
  def const(x: Double): NodeId = {
    require(!x.isNaN && !x.isInfinite, s"GraphBuilder: constant $x is not finite")
    node(Const(if (math.abs(x) < GraphBuilder.zeroBelow) 0.0 else x + 0.0))
  }

  def plus(a: NodeId, b: NodeId): NodeId = (constOf(a), constOf(b)) match {
    case (Some(x), Some(y)) => const(x + y)
    case (Some(0.0), _)     => b
    case (_, Some(0.0))     => a
    case _ =>
      (negOf(a), negOf(b)) match {
        case (_, Some(nb)) => minus(a, nb)
        case (Some(na), _) => minus(b, na)
        case _             => val (x, y) = ordered(a, b); node(Add(x, y))
      }
  }

  def minus(a: NodeId, b: NodeId): NodeId = (constOf(a), constOf(b)) match {
    case (Some(x), Some(y)) => const(x - y)
    case (_, Some(0.0))     => a
    case (Some(0.0), _)     => negate(b)
    case _ if a == b        => const(0.0)
    case _ =>
      (negOf(a), negOf(b)) match {
        case (_, Some(nb)) => plus(a, nb)
        case (Some(na), _) => negate(plus(na, b))
        case _             => node(Sub(a, b))
      }
  }

  def negate(a: NodeId): NodeId = nodes(a.index) match {
    case Const(v)                          => const(-v)
    case Neg(x)                            => x
    case Sub(x, y)                         => minus(y, x)
    case Mul(k, x) if constOf(k).isDefined => times(const(-constOf(k).get), x)
    case _                                 => node(Neg(a))
  }

  def times(a: NodeId, b: NodeId): NodeId = (constOf(a), constOf(b)) match {
    case (Some(x), Some(y)) => const(x * y)
    case (Some(_), None)    => scaled(constOf(a).get, b)
    case (None, Some(_))    => scaled(constOf(b).get, a)
    case _ =>
      (negOf(a), negOf(b)) match {
        case (Some(na), Some(nb)) => times(na, nb)
        case (Some(na), None)     => negate(times(na, b))
        case (None, Some(nb))     => negate(times(a, nb))
        case _                    => val (x, y) = ordered(a, b); node(Mul(x, y))
      }
  }

  /** k * x with a constant k: merged with a constant factor or negation already on x. */
  private def scaled(k: Double, x: NodeId): NodeId =
    if (k == 0.0) const(0.0)
    else if (k == 1.0) x
    else if (k == -1.0) negate(x)
    else
      nodes(x.index) match {
        case Neg(y)                            => scaled(-k, y)
        case Mul(c, y) if constOf(c).isDefined => scaled(k * constOf(c).get, y)
        case _                                 => node(Mul(const(k), x))
      }

  /**
   * The graph of `outputs` (unreachable nodes dropped, the rest renumbered in order), and the renumbering.
   */
  private def result(outputs: Seq[(String, NodeId)]): (Graph, Map[NodeId, NodeId]) = {
    val live = nodes.indices.reverse.foldLeft(outputs.map(_._2.index).toSet) { (keep, i) =>
      if (keep(i)) keep ++ nodes(i).operands.map(_.index) else keep
    }
    val kept = nodes.indices.filter(live)
    val renumber = kept.zipWithIndex.toMap
    def re(id: NodeId) = NodeId(renumber(id.index))
    val ops = kept.map(i =>
      nodes(i) match {
        case Add(a, b) => Add(re(a), re(b))
        case Sub(a, b) => Sub(re(a), re(b))
        case Neg(a)    => Neg(re(a))
        case Mul(a, b) => Mul(re(a), re(b))
        case leaf      => leaf
      }
    )
    (
      Graph(ops, outputs.map { case (name, id) => Output(name, re(id)) }.toIndexedSeq),
      renumber.map { case (a, b) => NodeId(a) -> NodeId(b) }
    )
  }
}

object GraphBuilder {
  val zeroBelow: Double = 1e-12

  /** Run `body` on a fresh builder; it returns the named outputs. */
  def build(body: GraphBuilder => Seq[(String, NodeId)]): Graph = {
    val b = new GraphBuilder
    b.result(body(b))._1
  }

  /**
   * As [[build]], with magnitude bounds the body proved for some nodes ([[RangeHints]]), carried to the final
   * numbering.
   */
  def buildWithBounds(
      body: GraphBuilder => (Seq[(String, NodeId)], Map[NodeId, Double])
  ): (Graph, RangeHints) = {
    val b = new GraphBuilder
    val (outputs, bounds) = body(b)
    val (graph, renumber) = b.result(outputs)
    (graph, RangeHints(bounds.collect { case (id, bound) if renumber.contains(id) => renumber(id) -> bound }))
  }
}
