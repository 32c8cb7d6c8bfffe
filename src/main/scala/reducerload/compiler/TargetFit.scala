package reducerload.compiler

import reducerload.arm.ArmParams
import reducerload.graph._

/** `numeric.target-error`: the fewest fraction bits whose derived bounds meet a target per torque. */
object TargetFit {

  /** A target per torque the datapath computes: one value for all, or one each. */
  def perOutput(p: ArmParams, targets: Seq[Double]): Seq[Double] = {
    val names = p.graph.outputs.map(_.name)
    targets.size match {
      case 1                    => Seq.fill(names.size)(targets.head)
      case n if n == names.size => targets
      case n =>
        throw new IllegalArgumentException(
          s"numeric.target-error gives $n values but ${p.chain.name} computes ${names.size} torque(s): ${names.mkString(", ")}"
        )
    }
  }

  /** Fraction-bit offsets tried for a target error: every kind of value moves together. */
  val fracBitShifts: Range = -16 to 16

  /** Each fraction-bit setting on its own, moved by some bits. */
  private val fracBitKinds: Seq[(ArmParams, Int) => ArmParams] = Seq(
    (q, d) => q.copy(datapath = q.datapath.copy(outputFracBits = q.outputFracBits + d)),
    (q, d) => q.copy(datapath = q.datapath.copy(constantFracBits = q.constantFracBits + d)),
    (q, d) => q.copy(datapath = q.datapath.copy(velocityFracBits = q.velocityFracBits + d)),
    (q, d) => q.copy(datapath = q.datapath.copy(accelerationFracBits = q.accelerationFracBits + d)),
    (q, d) => q.copy(datapath = q.datapath.copy(internalFracBits = q.internalFracBits + d))
  )

  /**
   * `p`'s fraction bits fitted to per-output targets: first every setting moved by the same number of bits,
   * the fewest for which each output's derived bound meets its target; then each kind of value on its own,
   * one bit at a time, while every bound still meets (kinds whose errors weigh little, often the constants'
   * or the output's, end up narrower than the rest); then each constant and product on its own (see
   * [[narrowedNodes]]), kept only if the design costs no more (see [[cost]]: mixed widths can split a shared
   * multiplier class in two). Fewer bits: narrower operands, adders and registers, fewer multiplier blocks
   * once an operand drops below a 17-bit chunk boundary. The graph does not change, only its analysis, so
   * each try costs one analysis.
   */
  def fitted(p: ArmParams, targets: Seq[Double]): ArmParams = {
    def shifted(d: Int) = scala.util
      .Try(p.copy(datapath = p.datapath.shifted(d)))
      .toOption
    def analysed(q: ArmParams, limits: FracBitLimits) =
      scala.util.Try(new Analysis(p.graph, q.numerics, p.rangeHints, limits)).toOption
    def bounds(q: ArmParams) = analysed(q, FracBitLimits.none).map(_.outputs.map(_.errorBound))
    def meets(a: Analysis) = a.outputs.map(_.errorBound).zip(targets).forall { case (b, t) => b <= t }
    @scala.annotation.tailrec
    def narrowed(q: ArmParams): ArmParams =
      fracBitKinds.iterator
        .flatMap(kind => scala.util.Try(kind(q, -1)).toOption)
        .find(q => analysed(q, FracBitLimits.none).exists(meets)) match {
        case Some(fewer) => narrowed(fewer)
        case None        => q
      }
    def perNode(q: ArmParams) = q.copy(fracBitLimits =
      narrowedNodes(analysed(q, FracBitLimits.none).get, limits => analysed(q, limits).filter(meets))
    )
    def cheaper(byKind: ArmParams) = Seq(perNode(byKind), byKind).minBy(cost)
    fracBitShifts.iterator
      .flatMap(shifted)
      .find(q => analysed(q, FracBitLimits.none).exists(meets))
      .map(q => cheaper(narrowed(q)))
      .getOrElse {
        val best = fracBitShifts.reverseIterator.flatMap(shifted).flatMap(bounds).next()
        val (worst, j) = best.zip(targets).map { case (b, t) => b / t }.zipWithIndex.maxBy(_._1)
        throw new IllegalArgumentException(
          f"numeric.target-error ${targets(j)}%.3g N·m for ${p.graph.outputs(j).name} cannot be met: with the most fraction bits (up to 40) " +
            f"its bound is ${best(j)}%.3g N·m, dominated by the sin/cos unit (raise cordic.output-bits)"
        )
      }
  }

  /**
   * What the target-error fit minimises, in order: the schedule's 18x18 blocks, its multiplier units (each
   * with its operand multiplexers and adder tree), then the bits of every node's format (the adders,
   * registers and memory words they take).
   */
  def cost(p: ArmParams): (Int, Int, Int) =
    (
      p.schedule.multiplierBlocks,
      p.schedule.multiplierUnits,
      p.graph.ids.map(id => p.analysis(id).format.width).sum
    )

  /**
   * Per-node caps from an analysis that meets its targets: each constant and product in turn loses one
   * fraction bit while `meeting` (the analysis under the caps, if every bound still meets) says yes, pass
   * after pass until none can. Turn by turn, so early nodes do not take the whole error budget; a constant is
   * not rounded to zero (its multiply would vanish from the graph).
   */
  def narrowedNodes(start: Analysis, meeting: FracBitLimits => Option[Analysis]): FracBitLimits = {
    val graph = start.graph
    val candidates =
      graph.ids.filter(id => graph(id) match { case Op.Const(_) | Op.Mul(_, _) => true; case _ => false })
    def keepsConstants(a: Analysis) = candidates.forall(id => a(id).raw.forall(_ != 0))
    @scala.annotation.tailrec
    def passes(limits: FracBitLimits, at: Analysis): FracBitLimits = {
      val (next, nextAt) = candidates.foldLeft((limits, at)) { case ((l, a), id) =>
        val bits = a(id).format.fracBits
        if (bits == 0) (l, a)
        else {
          val tried = l.capped(id, bits - 1);
          meeting(tried).filter(keepsConstants).fold((l, a))(t => (tried, t))
        }
      }
      if (next == limits) limits else passes(next, nextAt)
    }
    passes(start.limits, start)
  }

}
