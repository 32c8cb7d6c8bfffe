package reducerload.graph

import scala.collection.mutable

/** Whether the graph's sums are rebuilt for a shorter critical path (`datapath.reassociate`). */
sealed abstract class Reassociation(val name: String) { override def toString: String = name }
object Reassociation {

  /** The sums as RNEA writes them (left to right). */
  case object Off extends Reassociation("off")

  /** Every sum of several terms rebuilt as a tree, the earliest terms first ([[Reassociate]]). */
  case object Sums extends Reassociation("sums")

  val all: Seq[Reassociation] = Seq(Off, Sums)
}

/**
 * Clocks a value takes through each kind of operation, for the arrival estimate that orders a sum's terms:
 * relative figures, independent of any schedule, so that the rebuilt graph (and the per-node fraction-bit
 * caps fitted on it) is the same whatever the storage and interval.
 */
final case class ArrivalDelays(add: Int, mul: Int, trig: Int) {
  require(add >= 1 && mul >= 1 && trig >= 0, s"ArrivalDelays: $this")
}

/**
 * Rebuilds every sum of several terms as a tree: RNEA writes `a + b + c + d` left to right, so a term that
 * arrives late (the recursion's value from the previous link) may pass through every addition after it. Each
 * maximal tree of additions, subtractions and negations whose inner nodes have one reader is flattened into
 * signed terms and summed again, the two earliest terms first (by an arrival estimate with
 * [[ArrivalDelays]]): the greedy pairing that minimises the latest arrival of the sum.
 *
 * The value of every kept node is unchanged, and the fixed-point sums are exact (aligned, not rounded): the
 * analysis of the rebuilt graph derives its formats and bounds anew, which move only where a kept node's
 * interval does (its partial sums and their hints are new). Two things stay as they are: `cos(q) u +- sin(q)
 * w` (a rotation, whose bound [[Analysis]] tightens, is kept as one term) and every node with more than one
 * reader (sharing is kept). The range hints of kept nodes carry over; those of the dropped inner sums are
 * lost (their partial sums no longer exist).
 */
object Reassociate {
  import Op._

  private def isSum(op: Op): Boolean = op match {
    case _: Add | _: Sub | _: Neg => true
    case _                        => false
  }

  /** `cos(q) u` and `sin(q) w` of the same angle: the pattern [[Analysis]] bounds by hypot. */
  private def isRotation(graph: Graph, a: NodeId, b: NodeId): Boolean = {
    def split(m: NodeId): Option[(TrigFn, AngleSum)] = graph(m) match {
      case Mul(x, y) =>
        (graph(x), graph(y)) match {
          case (Trig(fn, angle), _) => Some((fn, angle))
          case (_, Trig(fn, angle)) => Some((fn, angle))
          case _                    => None
        }
      case _ => None
    }
    (split(a), split(b)) match {
      case (Some((fa, qa)), Some((fb, qb))) => qa == qb && fa != fb
      case _                                => false
    }
  }

  /**
   * A signed term of a flattened sum, with its new node and arrival; `order` breaks ties (first term first).
   */
  private final case class Term(node: NodeId, arrival: Int, negative: Boolean, order: Int)

  def apply(graph: Graph, hints: RangeHints, delays: ArrivalDelays): (Graph, RangeHints) = {
    val readers = Array.fill(graph.ops.size)(0)
    val reader = Array.fill(graph.ops.size)(-1)
    graph.ids.foreach(id =>
      graph(id).operands.foreach { x => readers(x.index) += 1; reader(x.index) = id.index }
    )
    graph.outputs.foreach(o => readers(o.node.index) += 1)
    def rotation(i: Int): Boolean = graph.ops(i) match {
      case Add(a, b) => isRotation(graph, a, b)
      case Sub(a, b) => isRotation(graph, a, b)
      case _         => false
    }
    // An inner node of a sum tree: a sum with one reader, itself a sum (outputs are read by the port).
    val inner: IndexedSeq[Boolean] = graph.ops.indices.map(i =>
      isSum(graph.ops(i)) && !rotation(i) && readers(i) == 1 && reader(i) >= 0 && isSum(graph.ops(reader(i)))
    )

    GraphBuilder.buildWithBounds { b =>
      val built = Array.fill(graph.ops.size)(NodeId(-1))
      val arrival = Array.fill(graph.ops.size)(0)

      /** The signed terms of the tree under node `i` (inner nodes expanded, every other node a term). */
      def terms(i: Int, negative: Boolean): Seq[(Int, Boolean)] = {
        def term(x: NodeId, neg: Boolean) = if (inner(x.index)) terms(x.index, neg) else Seq(x.index -> neg)
        graph.ops(i) match {
          case Add(x, y) => term(x, negative) ++ term(y, negative)
          case Sub(x, y) => term(x, negative) ++ term(y, !negative)
          case Neg(x)    => term(x, !negative)
          case other     => throw new IllegalStateException(s"Reassociate: $other is no sum")
        }
      }

      /** The terms summed two earliest first; a negative total negated at the end. */
      def balanced(leaves: Seq[(Int, Boolean)]): (NodeId, Int) = {
        val queue = mutable.PriorityQueue.empty[Term](Ordering.by((t: Term) => (t.arrival, t.order)).reverse)
        leaves.zipWithIndex.foreach { case ((x, neg), k) => queue += Term(built(x), arrival(x), neg, k) }
        var next = leaves.size
        while (queue.size > 1) {
          val (p, q) = (queue.dequeue(), queue.dequeue())
          val (node, negative) = (p.negative, q.negative) match {
            case (false, false) => (b.plus(p.node, q.node), false)
            case (true, true)   => (b.plus(p.node, q.node), true)
            case (false, true)  => (b.minus(p.node, q.node), false)
            case (true, false)  => (b.minus(q.node, p.node), false)
          }
          queue += Term(node, math.max(p.arrival, q.arrival) + delays.add, negative, next)
          next += 1
        }
        val last = queue.dequeue()
        if (last.negative) (b.negate(last.node), last.arrival + delays.add) else (last.node, last.arrival)
      }

      graph.ids.foreach { id =>
        val i = id.index
        def in(x: NodeId) = built(x.index)
        def after(xs: NodeId*) = xs.map(x => arrival(x.index)).max
        if (!inner(i)) {
          val (node, at) = graph(id) match {
            case Const(v)                 => (b.const(v), 0)
            case Input(s)                 => (b.input(s), 0)
            case Trig(fn, angle)          => (b.trig(fn, angle), delays.trig)
            case Mul(x, y)                => (b.times(in(x), in(y)), after(x, y) + delays.mul)
            case Add(x, y) if rotation(i) => (b.plus(in(x), in(y)), after(x, y) + delays.add)
            case Sub(x, y) if rotation(i) => (b.minus(in(x), in(y)), after(x, y) + delays.add)
            case _: Add | _: Sub | _: Neg => balanced(terms(i, negative = false))
          }
          built(i) = node
          arrival(i) = at
        }
      }
      // Every kept node has its old value: its proven bound holds for the new node (the tighter if two meet).
      val bounds = hints.bounds.toSeq
        .collect { case (id, bound) if !inner(id.index) => built(id.index) -> bound }
        .groupMapReduce(_._1)(_._2)(math.min)
      (graph.outputs.map(o => o.name -> built(o.node.index)), bounds)
    }
  }

  /**
   * Cycles from the inputs to the latest output by `delays` (constants and inputs at 0), for reports and
   * tests.
   */
  def depth(graph: Graph, delays: ArrivalDelays): Int = {
    val at = graph.fold[Int] { (op, arrival) =>
      op match {
        case Const(_) | Input(_) => 0
        case Trig(_, _)          => delays.trig
        case Mul(x, y)           => math.max(arrival(x), arrival(y)) + delays.mul
        case other               => other.operands.map(arrival).max + delays.add
      }
    }
    graph.outputs.map(o => at(o.node.index)).maxOption.getOrElse(0)
  }
}
