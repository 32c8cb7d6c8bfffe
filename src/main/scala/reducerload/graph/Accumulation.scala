package reducerload.graph

/**
 * A tree of additions summed by an accumulator (`schedule.accumulate-slack`): its products leave their
 * multiplier units in residues of their own within an interval, each into a register its unit keeps for the
 * rounded products of the accumulators, from there into the accumulator's term register, and the accumulator
 * adds each to the partial sum. The products get no register of their own, the sums below the root no adder;
 * the root's register is loaded from the accumulator's adder with the last product,
 * [[Accumulation.rootDelay]] clocks after that product would have been in its own register. Sums in the graph
 * are exact (every operand aligned up to the sum's fraction bits, the sum's format proven to hold it), so the
 * root's value is the signed sum of the products aligned to its fraction bits, and an accumulator as wide as
 * the root gives it even where a partial sum would not fit (two's complement wraps back): the bit-accurate
 * model does not change.
 *
 * @param root
 *   the sum whose value the tree computes, read by the rest of the graph
 * @param inner
 *   the sums below the root, each read once, by a sum of the tree: no adder, no register
 * @param terms
 *   the products the tree adds, each read once, by a sum of the tree, with its sign in the root
 */
final case class Accumulation(root: NodeId, inner: Seq[NodeId], terms: Seq[Accumulation.Term]) {
  require(terms.size >= 2, s"Accumulation: a tree of ${terms.size} products")
  def products: Seq[NodeId] = terms.map(_.product)

  /** The sums of the tree, the root first. */
  def sums: Seq[NodeId] = root +: inner
}

object Accumulation {

  /** A product of an accumulated tree, subtracted from the root when `negated`. */
  final case class Term(product: NodeId, negated: Boolean)

  /**
   * Registers between a product in its unit's register of rounded products and the accumulator's adder: the
   * term register (selected among units, complemented where subtracted). The rounding's carry chain, the
   * selection and the accumulator's carry chain in one clock, then the selection and the carry chain, were
   * the longest paths of the UR5's design.
   */
  val termRegisters: Int = 1

  /**
   * Clocks from the cycle an accumulated tree's last product would be in its own register to the cycle its
   * root is: through the [[termRegisters]], then the accumulator's adder into the root's register.
   */
  val rootDelay: Int = termRegisters + 1

  /**
   * Clocks an accumulated tree of `k` products ready in the same cycle takes over the same tree on adders: in
   * residues of their own they are ready one per clock, the root [[rootDelay]] after the last, where a tree
   * of adders takes ceil(log2 k) levels from the products, the first level a clock after them.
   */
  def latencyCost(k: Int): Int = k - 1 + rootDelay - (32 - Integer.numberOfLeadingZeros(k - 1))

  /**
   * The largest trees of additions (and subtractions) in `graph` whose leaves are all products `onUnit` read
   * once, by a sum of the tree, with two products or more; a sum below a root is read once, by a sum of the
   * tree, and is not an output.
   */
  def find(graph: Graph, onUnit: NodeId => Boolean): IndexedSeq[Accumulation] = {
    import Op._
    def isSum(id: NodeId) = graph(id) match { case _: Add | _: Sub => true; case _ => false }
    val readOnce = graph.readers.map(_ == 1)
    // whether a sum's leaves are all products on a unit read by it alone (in graph order: operands first)
    val pure = graph.ids.foldLeft(Vector.empty[Boolean]) { (done, id) =>
      def leaf(x: NodeId) =
        readOnce(x.index) && (graph(x) match {
          case _: Mul => onUnit(x)
          case _      => isSum(x) && done(x.index)
        })
      done :+ (isSum(id) && graph(id).operands.forall(leaf))
    }
    val readBy = Array.fill(graph.ops.size)(Option.empty[NodeId])
    graph.ids.foreach(id => graph(id).operands.foreach(x => readBy(x.index) = Some(id)))
    def inside(s: NodeId) = readOnce(s.index) && readBy(s.index).exists(r => pure(r.index))
    def terms(s: NodeId, negated: Boolean): Seq[Term] = {
      val (a, b, subtracts) = graph(s) match {
        case Add(a, b) => (a, b, false)
        case Sub(a, b) => (a, b, true)
        case op        => throw new IllegalStateException(s"Accumulation: $op is no sum")
      }
      def leaf(x: NodeId, neg: Boolean) = if (isSum(x)) terms(x, neg) else Seq(Term(x, neg))
      leaf(a, negated) ++ leaf(b, negated != subtracts)
    }
    def below(s: NodeId): Seq[NodeId] = graph(s).operands.filter(isSum).flatMap(x => x +: below(x))
    graph.ids
      .filter(s => pure(s.index) && !inside(s))
      .map(s => Accumulation(s, below(s), terms(s, negated = false)))
  }
}
