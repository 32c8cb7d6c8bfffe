package reducerload.graph

/**
 * Magnitude bounds on some nodes' exact values, proved by whoever built the graph from facts the scalar
 * operations cannot see (a rotation keeps a vector's length; |a x b| <= |a| |b|). The [[Analysis]] intersects
 * each node's interval with its hint: both are sound, the tighter wins.
 */
final case class RangeHints(bounds: Map[NodeId, Double]) {
  bounds.foreach { case (id, b) => require(b >= 0 && !b.isNaN, s"RangeHints: node ${id.index} has bound $b") }
  def apply(id: NodeId): Option[Double] = bounds.get(id)
}

object RangeHints {
  val none: RangeHints = RangeHints(Map.empty)
}
