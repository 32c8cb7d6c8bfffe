package reducerload.graph

import reducerload.app.Cli

/**
 * How much of a design's logic sits in sums of products: a benchmark, not a test. A product read once, by an
 * addition, needs a capture register (its unit moves on) and that addition an adder; the products of one tree
 * of such additions accumulated on one unit would need neither, only the unit's accumulator and the tree's
 * root. Prints the trees by their leaves, the bits they hold, and which trees could be accumulated within a
 * latency allowed over the dependences' bound (each tree judged alone: trees on one chain share their slack,
 * so the last table is an upper bound):
 *
 * {{{
 * ./sbt "Test/runMain reducerload.graph.SumTreeCensus --robot golden/robots/ur5_robot.urdf --tip tool0
 *   --max-acceleration 15 --target-error 1e-3 --clocks-per-sample 18 --datapath.registered-routes true"
 * }}}
 *
 * The arguments are a design as `run emit` takes it (the graph, its formats and its operators' latencies).
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
    // Slack by the dependences alone (a unit free whenever asked): each node's ready cycle, its longest chain
    // of latencies to an output, and the tree's root's distance from the longest chain. k products on one unit
    // are ready k - 1 clocks after the first, plus the accumulator's clock, where the tree sums them in
    // ceil(log2 k) levels: the tree can be accumulated at no latency when its root's slack covers the difference.
    val schedule = arm.schedule
    def own(id: NodeId): Int = g(id) match {
      case _: Op.Mul                 => schedule.mulLatency(id)
      case _: Op.Trig                => schedule.trigLatency
      case _: Op.Const | _: Op.Input => 0
      case _                         => 1
    }
    val ready = g.ids.foldLeft(Vector.empty[Int]) { (r, id) =>
      r :+ (g(id) match {
        case _: Op.Const       => 0
        case _: Op.Input       => schedule.inputCycle
        case Op.Trig(_, angle) => Schedule.firstAngleCycle + schedule.angleSumStages(angle) + own(id)
        case op                => op.operands.map(o => r(o.index)).max + own(id)
      })
    }
    val height = g.ids.reverse.foldLeft(Map.empty[Int, Int]) { (h, id) =>
      h + (id.index -> (own(id) + readBy(id.index).map(u => h(u.index)).maxOption.getOrElse(0)))
    }
    val bound = g.outputs.map(o => ready(o.node.index)).max
    def slack(id: NodeId) = bound - (ready(id.index) + height(id.index) - own(id))
    def extra(k: Int) = k - (32 - Integer.numberOfLeadingZeros(k - 1))
    println(
      s"trees with two or more such products: ${kept.size}; their products ${products.size} (${products.map(width).sum} " +
        s"capture bits), the sums inside them ${kept.map(_._2.size).sum} (${kept.flatMap(_._2).map(width).sum} adder " +
        s"bits), roots ${kept.size} (${kept.map(t => width(t._1)).sum} bits); products of one fraction-bit count in " +
        s"${kept.count(t => t._3.filter(accumulable).map(arm.analysis(_).format.fracBits).distinct.size == 1)} trees"
    )
    println()
    println(
      "| latency allowed over the dependences' | trees accumulated | products | capture bits | sums | adder bits |"
    )
    println("| --- | --- | --- | --- | --- | --- |")
    Seq(0, 4, 9, 16).foreach { more =>
      val free = kept.filter(t => slack(t._1) + more >= extra(t._3.count(accumulable)))
      val freeProducts = free.flatMap(_._3.filter(accumulable))
      println(
        s"| +$more clocks (ready by ${bound + more}) | ${free.size} | ${freeProducts.size} | ${freeProducts.map(width).sum} | " +
          s"${free.map(_._2.size).sum} | ${free.flatMap(_._2).map(width).sum} |"
      )
    }
  }
}
