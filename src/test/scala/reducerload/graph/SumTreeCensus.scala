package reducerload.graph

import reducerload.app.Cli

/**
 * How much of a design's logic sits in sums of products: a benchmark, not a test. A product read once, by an
 * addition, needs a capture register (its unit moves on) and that addition an adder; the products of one tree
 * of such additions accumulated (`schedule.accumulate-slack`, [[Accumulation]]) need neither, only the tree's
 * accumulator and root. Prints the trees by their leaves, the bits they hold, and which trees could be
 * accumulated within a latency allowed over the dependences' bound (each tree judged alone: trees on one
 * chain share their slack, so the last table is an upper bound):
 *
 * {{{
 * ./sbt "Test/runMain reducerload.graph.SumTreeCensus --robot golden/robots/ur5_robot.urdf --tip tool0
 *   --max-acceleration 15 --target-error 1e-3 --clocks-per-sample 18 --datapath.registered-routes true"
 * }}}
 *
 * The arguments are a design as `run emit` takes it (the graph, its formats and its operators' latencies).
 */
object SumTreeCensus {

  /** A sum (`root`), the sums below it read by it alone (`sums`, the root included) and what they read. */
  private final case class Tree(root: NodeId, sums: Seq[NodeId], leaves: Seq[NodeId])

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
    val trees = g.ids.filter(s => isSum(s) && !readOnceBySum(s)).map(r => Tree(r, inside(r), leaves(r)))
    val kept = trees.filter(_.leaves.count(accumulable) >= 2)
    val products = kept.flatMap(_.leaves.filter(accumulable))
    println(
      s"${muls.size} products (${muls.map(width).sum} bits), ${accumulable.size} of them read once by a sum"
    )
    println()
    println("| leaves | of them products read once | trees |")
    println("| --- | --- | --- |")
    trees
      .groupBy(t => (t.leaves.size, t.leaves.count(accumulable)))
      .toSeq
      .sortBy(_._1)
      .foreach { case ((n, p), ts) => println(s"| $n | $p | ${ts.size} |") }
    println()
    // A tree can be accumulated at no latency when its root's slack by the dependences alone
    // ([[Schedule.slack]]) covers what accumulating it costs ([[Accumulation.latencyCost]]).
    val schedule = arm.schedule
    println(
      s"trees with two or more such products: ${kept.size}; their products ${products.size} (${products.map(width).sum} " +
        s"capture bits), the sums inside them ${kept.map(_.sums.size).sum} (${kept.flatMap(_.sums).map(width).sum} adder " +
        s"bits), roots ${kept.size} (${kept.map(t => width(t.root)).sum} bits); products of one fraction-bit count in " +
        s"${kept.count(t => t.leaves.filter(accumulable).map(arm.analysis(_).format.fracBits).distinct.size == 1)} trees"
    )
    println()
    println(
      s"| latency allowed over the dependences' ${schedule.dependenceBound} cycles | trees accumulated | products | " +
        "capture bits | sums | adder bits |"
    )
    println("| --- | --- | --- | --- | --- | --- |")
    Seq(0, 4, 9, 16).foreach { more =>
      val free = kept.filter(t =>
        schedule.slack(t.root.index) + more >= Accumulation.latencyCost(t.leaves.count(accumulable))
      )
      val freeProducts = free.flatMap(_.leaves.filter(accumulable))
      println(
        s"| +$more | ${free.size} | ${freeProducts.size} | ${freeProducts.map(width).sum} | " +
          s"${free.map(_.sums.size).sum} | ${free.flatMap(_.sums).map(width).sum} |"
      )
    }
  }
}
