package reducerload.graph

import reducerload.app.Cli

/**
 * How much of a design's logic sits in sums of products: a benchmark, not a test. A product read once, by an
 * addition, needs a capture register (its unit moves on) and that addition an adder; the products of one tree
 * of such additions accumulated on one unit would need neither, only the unit's accumulator and the tree's
 * root. Prints the trees by their leaves and the bits they hold:
 *
 * {{{
 * ./sbt "Test/runMain reducerload.graph.SumTreeCensus --robot golden/robots/ur5_robot.urdf --tip tool0
 *   --max-acceleration 15 --target-error 1e-3 --clocks-per-sample 18"
 * }}}
 *
 * The arguments are a design as `run emit` takes it (the graph and its formats; the schedule is not used).
 */
object SumTreeCensus {

  def main(args: Array[String]): Unit = {
    val arm = Cli.parse("emit", args.toSeq, Nil).compiled.arm
    val g = arm.graph
    def width(id: NodeId) = arm.analysis(id).format.width
    def isSum(id: NodeId) = g(id) match { case _: Op.Add | _: Op.Sub => true; case _ => false }
    val readBy = Array.fill(g.ops.size)(List.empty[NodeId])
    g.ids.foreach(id => g(id).operands.foreach(o => readBy(o.index) ::= id))
    def readOnceBySum(id: NodeId) = g.readers(id.index) == 1 && readBy(id.index).exists(isSum)
    val muls = g.ids.filter(g(_).isInstanceOf[Op.Mul])
    val accumulable = muls.filter(readOnceBySum).toSet
    // A tree: a sum and the sums below it read by it alone; its leaves are what those sums read.
    def inside(s: NodeId): Seq[NodeId] =
      s +: g(s).operands.filter(o => isSum(o) && readOnceBySum(o)).flatMap(inside)
    def leaves(s: NodeId): Seq[NodeId] =
      inside(s).flatMap(g(_).operands).filterNot(o => isSum(o) && readOnceBySum(o))
    val trees = g.ids.filter(s => isSum(s) && !readOnceBySum(s)).map(r => (r, inside(r), leaves(r)))
    val kept = trees.filter(_._3.count(accumulable) >= 2)
    val products = kept.flatMap(_._3.filter(accumulable))
    println(
      s"${muls.size} products (${muls.map(width).sum} bits), ${accumulable.size} of them read once by a sum"
    )
    println()
    println("| leaves | of them products read once | trees |")
    println("| --- | --- | --- |")
    trees
      .groupBy(t => (t._3.size, t._3.count(accumulable)))
      .toSeq
      .sortBy(_._1)
      .foreach { case ((n, p), ts) => println(s"| $n | $p | ${ts.size} |") }
    println()
    println(
      s"trees with two or more such products: ${kept.size}; their products ${products.size} (${products.map(width).sum} " +
        s"capture bits), the sums inside them ${kept.map(_._2.size).sum} (${kept.flatMap(_._2).map(width).sum} adder " +
        s"bits), roots ${kept.size} (${kept.map(t => width(t._1)).sum} bits); products of one fraction-bit count in " +
        s"${kept.count(t => t._3.filter(accumulable).map(arm.analysis(_).format.fracBits).distinct.size == 1)} trees"
    )
  }
}
