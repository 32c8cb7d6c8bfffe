package reducerload.graph

/**
 * Per-node caps on fraction bits, below what a node's kind would give it: a constant is rounded to at most
 * this many, a product drops to at most this many (with the product rounding). The target-error fit chooses
 * them (`ArmConfig.fitted`); a node without a cap follows its kind's rule in [[Analysis]]. Keyed by node:
 * valid for the graph it was fitted on.
 */
final case class FracBitLimits(byNode: Map[NodeId, Int]) {
  byNode.foreach { case (id, bits) =>
    require(bits >= 0 && bits <= 62, s"FracBitLimits: node ${id.index} capped at $bits fraction bits (0..62)")
  }
  def apply(id: NodeId): Option[Int] = byNode.get(id)
  def capped(id: NodeId, bits: Int): FracBitLimits = FracBitLimits(byNode + (id -> bits))
  def isEmpty: Boolean = byNode.isEmpty
}

object FracBitLimits {
  val none: FracBitLimits = FracBitLimits(Map.empty)
}
