package reducerload.graph

import scala.collection.mutable

/**
 * Whether the graph's sums, and its products, are rebuilt for a shorter critical path
 * (`datapath.reassociate`).
 */
sealed abstract class Reassociation(val name: String) { override def toString: String = name }
object Reassociation {

  /** The sums and products as RNEA writes them (left to right). */
  case object Off extends Reassociation("off")

  /** Every sum of several terms rebuilt as a tree, the earliest terms first ([[Reassociate]]). */
  case object Sums extends Reassociation("sums")

  /**
   * As [[Sums]], every product of several factors rebuilt the same way, and the constants on the critical
   * path pushed into the sums they scale ([[Reassociate]], [[Reassociate.distributeConstants]]).
   */
  case object SumsAndProducts extends Reassociation("sums-and-products")

  val all: Seq[Reassociation] = Seq(Off, Sums, SumsAndProducts)
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
 *
 * With `products`, each maximal tree of multiplications whose inner products have one reader is flattened
 * into factors the same way, its constants multiplied into one, and multiplied again two earliest first:
 * `cos(q) (k x)`, with `x` late and `k x` read only there, becomes `(k cos(q)) x`, a product off the critical
 * path. A product that multiplies a sin/cos directly keeps it as a factor of its last multiplication (with
 * the tree's constant, if any: `(k cos(q)) u`), the shape [[Analysis]] bounds as a rotation. Products are
 * rounded, so unlike the sums the datapath's values move by their roundings; the analysis derives the new
 * bounds.
 */
object Reassociate {
  import Op._

  private def isSum(op: Op): Boolean = op match {
    case _: Add | _: Sub | _: Neg => true
    case _                        => false
  }

  /**
   * A signed term of a flattened sum, with its new node and arrival; `order` breaks ties (first term first).
   */
  private final case class Term(node: NodeId, arrival: Int, negative: Boolean, order: Int)

  def apply(
      graph: Graph,
      hints: RangeHints,
      delays: ArrivalDelays,
      products: Boolean = false
  ): (Graph, RangeHints) = {
    val readers = graph.readers
    val reader = Array.fill(graph.ops.size)(-1)
    graph.ids.foreach(id => graph(id).operands.foreach(x => reader(x.index) = id.index))
    def rotation(i: Int): Boolean = Rotation.isRotation(graph, NodeId(i))
    // An inner node of a sum tree: a sum with one reader, itself a sum (outputs are read by the port).
    val inner: IndexedSeq[Boolean] = graph.ops.indices.map(i =>
      isSum(graph.ops(i)) && !rotation(i) && readers(i) == 1 && reader(i) >= 0 && isSum(graph.ops(reader(i)))
    )
    // An inner node of a product tree: a product with one reader, itself a product.
    def isMul(op: Op) = op.isInstanceOf[Mul]
    val innerMul: IndexedSeq[Boolean] = graph.ops.indices.map(i =>
      products && isMul(graph.ops(i)) && readers(i) == 1 && reader(i) >= 0 && isMul(graph.ops(reader(i)))
    )
    def dropped(i: Int) = inner(i) || innerMul(i)

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

      /**
       * `leaves` combined two earliest first (of equal arrivals, the first given), the greedy pairing that
       * minimises the latest arrival: `combine` gives a pair's node and sign, which arrives `delay` after the
       * later of the two.
       */
      def earliestFirst(leaves: Seq[(NodeId, Int, Boolean)], delay: Int)(
          combine: (Term, Term) => (NodeId, Boolean)
      ): Term = {
        val queue = mutable.PriorityQueue.empty[Term](Ordering.by((t: Term) => (t.arrival, t.order)).reverse)
        leaves.zipWithIndex.foreach { case ((x, at, neg), k) => queue += Term(x, at, neg, k) }
        var next = leaves.size
        while (queue.size > 1) {
          val (p, q) = (queue.dequeue(), queue.dequeue())
          val (node, negative) = combine(p, q)
          queue += Term(node, math.max(p.arrival, q.arrival) + delay, negative, next)
          next += 1
        }
        queue.dequeue()
      }

      /** The terms summed two earliest first; a negative total negated at the end. */
      def balanced(leaves: Seq[(Int, Boolean)]): (NodeId, Int) = {
        val last = earliestFirst(leaves.map { case (x, neg) => (built(x), arrival(x), neg) }, delays.add) {
          (p, q) =>
            (p.negative, q.negative) match {
              case (false, false) => (b.plus(p.node, q.node), false)
              case (true, true)   => (b.plus(p.node, q.node), true)
              case (false, true)  => (b.minus(p.node, q.node), false)
              case (true, false)  => (b.minus(q.node, p.node), false)
            }
        }
        if (last.negative) (b.negate(last.node), last.arrival + delays.add) else (last.node, last.arrival)
      }

      /** The factors of the product tree under node `i` (inner products expanded). */
      def factors(i: Int): Seq[Int] =
        graph.ops(i).operands.flatMap(x => if (innerMul(x.index)) factors(x.index) else Seq(x.index))

      /** The product of `leaves`, two earliest first. */
      def multiplied(leaves: Seq[(NodeId, Int)]): (NodeId, Int) = {
        val last = earliestFirst(leaves.map { case (x, at) => (x, at, false) }, delays.mul)((p, q) =>
          (b.times(p.node, q.node), false)
        )
        (last.node, last.arrival)
      }

      /**
       * The product tree under node `i` rebuilt: its constants as one, then two earliest first; a sin/cos
       * that `i` multiplies directly stays a factor of the last multiplication, scaled by the constant.
       */
      def product(i: Int): (NodeId, Int) = {
        val (constants, variables) = factors(i).partition(x => graph.ops(x).isInstanceOf[Const])
        val k = constants.map(x => graph.ops(x).asInstanceOf[Const].value).product
        def leaf(x: Int) = built(x) -> arrival(x)
        val constant = if (constants.isEmpty) Nil else Seq(b.const(k) -> 0)
        graph.ops(i).operands.map(_.index).find(x => graph.ops(x).isInstanceOf[Trig]) match {
          case Some(t) =>
            val scaled = multiplied(constant :+ leaf(t))
            variables.diff(Seq(t)) match {
              case Seq() => scaled
              case rest =>
                val (u, at) = multiplied(rest.map(leaf))
                (b.times(scaled._1, u), math.max(scaled._2, at) + delays.mul)
            }
          case None => multiplied(constant ++ variables.map(leaf))
        }
      }

      graph.ids.foreach { id =>
        val i = id.index
        def in(x: NodeId) = built(x.index)
        def after(xs: NodeId*) = xs.map(x => arrival(x.index)).max
        if (!dropped(i)) {
          val (node, at) = graph(id) match {
            case Const(v)                 => (b.const(v), 0)
            case Input(s)                 => (b.input(s), 0)
            case Trig(fn, angle)          => (b.trig(fn, angle), delays.trig)
            case Mul(_, _) if products    => product(i)
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
        .collect { case (id, bound) if !dropped(id.index) => built(id.index) -> bound }
        .groupMapReduce(_._1)(_._2)(math.min)
      (graph.outputs.map(o => o.name -> built(o.node.index)), bounds)
    }
  }

  /**
   * Constants on the critical path pushed into the sums they scale (`datapath.reassociate =
   * sums-and-products`): `k (cos(q) a - sin(q) b)`, where the sum arrives late, becomes `(k cos(q)) a - (k
   * sin(q)) b`, whose constant products are ready as soon as the sin/cos, so the multiply by `k` leaves the
   * critical path. One round distributes every multiply by a constant on the critical path (by `delays`) over
   * the sum it scales, when that sum has no other reader or is a rotation (whose two products are then
   * computed twice): into each term with one reader, a product's earlier factor taking the constant, any
   * other term multiplied as a whole. Rounds repeat while the latest output moves earlier, since each may
   * expose other constants on the new critical path. Each product term costs a product more (`k cos(q)`,
   * unless the graph has it already), which is why only critical constants are distributed.
   */
  def distributeConstants(graph: Graph, hints: RangeHints, delays: ArrivalDelays): (Graph, RangeHints) = {
    val rounds = Iterator.iterate(Option((graph, hints))) {
      case Some((g, h)) =>
        distributedOnce(g, h, delays).filter { case (d, _) => depth(d, delays) < depth(g, delays) }
      case None => None
    }
    rounds.takeWhile(_.isDefined).flatten.toSeq.last
  }

  private def distributedOnce(
      graph: Graph,
      hints: RangeHints,
      delays: ArrivalDelays
  ): Option[(Graph, RangeHints)] = {
    val at = arrivals(graph, delays)
    val readers = graph.readers
    // The latest cycle each node may arrive at without moving the latest output.
    val required = Array.fill(graph.ops.size)(Int.MaxValue)
    graph.outputs.foreach(o => required(o.node.index) = depth(graph, delays))
    graph.ids.reverse.foreach { id =>
      val start = required(id.index) - own(graph(id), delays)
      graph(id).operands.foreach(x => required(x.index) = math.min(required(x.index), start))
    }
    def constant(x: NodeId) = graph(x) match { case Const(v) => Some(v); case _ => None }
    def rotation(x: NodeId) = Rotation.isRotation(graph, x)

    /** A critical multiply by a constant of a sum: the constant and the sum. */
    def scaledSum(id: NodeId): Option[(Double, NodeId)] = graph(id) match {
      case Mul(a, b) if at(id.index) == required(id.index) =>
        Seq(a -> b, b -> a).collectFirst {
          case (k, x) if constant(k).isDefined && (readers(x.index) == 1 && isSum(graph(x)) || rotation(x)) =>
            constant(k).get -> x
        }
      case _ => None
    }
    val chosen = graph.ids.flatMap(id => scaledSum(id).map(id -> _)).toMap
    if (chosen.isEmpty) None
    else
      Some(GraphBuilder.buildWithBounds { b =>
        val built = Array.fill(graph.ops.size)(NodeId(-1))
        def in(x: NodeId) = built(x.index)

        /** k times node `n` (of the old graph, read only by this), pushed into its sum's terms. */
        def distributed(k: Double, n: NodeId, top: Boolean = false): NodeId = graph(n) match {
          case Add(x, y) if top || readers(n.index) == 1 =>
            b.plus(distributed(k, x, top), distributed(k, y, top))
          case Sub(x, y) if top || readers(n.index) == 1 =>
            b.minus(distributed(k, x, top), distributed(k, y, top))
          case Neg(x) if readers(n.index) == 1 => b.negate(distributed(k, x))
          case Mul(x, y) if top || readers(n.index) == 1 =>
            val (early, late) = if (at(x.index) <= at(y.index)) (x, y) else (y, x)
            b.times(b.times(b.const(k), in(early)), in(late))
          case _ => b.times(b.const(k), in(n))
        }
        graph.ids.foreach { id =>
          built(id.index) = chosen.get(id) match {
            case Some((k, x)) => distributed(k, x, top = rotation(x))
            case None =>
              graph(id) match {
                case Const(v)        => b.const(v)
                case Input(s)        => b.input(s)
                case Trig(fn, angle) => b.trig(fn, angle)
                case Mul(x, y)       => b.times(in(x), in(y))
                case Add(x, y)       => b.plus(in(x), in(y))
                case Sub(x, y)       => b.minus(in(x), in(y))
                case Neg(x)          => b.negate(in(x))
              }
          }
        }
        // Every node keeps its value: its proven bound holds for the new node.
        val bounds = hints.bounds.toSeq
          .map { case (id, bound) => built(id.index) -> bound }
          .groupMapReduce(_._1)(_._2)(math.min)
        (graph.outputs.map(o => o.name -> built(o.node.index)), bounds)
      })
  }

  private def own(op: Op, delays: ArrivalDelays): Int = op match {
    case Const(_) | Input(_) => 0
    case Trig(_, _)          => delays.trig
    case Mul(_, _)           => delays.mul
    case _                   => delays.add
  }

  /** Each node's arrival by `delays` (constants and inputs at 0). */
  private def arrivals(graph: Graph, delays: ArrivalDelays): IndexedSeq[Int] =
    graph.fold[Int]((op, arrival) => op.operands.map(arrival).maxOption.getOrElse(0) + own(op, delays))

  /**
   * Cycles from the inputs to the latest output by `delays` (constants and inputs at 0), for reports and
   * tests.
   */
  def depth(graph: Graph, delays: ArrivalDelays): Int = {
    val at = arrivals(graph, delays)
    graph.outputs.map(o => at(o.node.index)).maxOption.getOrElse(0)
  }
}
