package reducerload.graph

import reducerload.fixedpoint.{FixedFormat, Rounding}

/**
 * What the analysis proves about one node: the exact value lies in `range` for every input within the
 * declared ranges, the datapath's value differs from it by at most `error`, and both fit `format`. For a
 * constant, `raw` is its code.
 */
final case class NodeNumerics(
    range: Interval,
    error: Double,
    format: FixedFormat,
    raw: Option[BigInt] = None
) {

  /** Largest magnitude the datapath can hold at this node. */
  def computedMaxAbs: Double = range.maxAbs + error
}

/**
 * How one multiply reaches its format: the fraction bits it keeps, the bits it drops and the rounding that
 * drops them.
 */
final case class ProductRounding(keep: Int, drop: Int, rounding: Rounding) {
  require(drop >= 0, s"ProductRounding: cannot drop $drop bits")

  /** Worst-case error of the dropping, in value units. */
  def errorBound: Double = if (drop > 0) Rounding.maxErrorLsb(rounding) * math.pow(2.0, -keep) else 0.0
}

/** One output after the output stage: its format, range and error bound (N·m). */
final case class OutputNumerics(name: String, range: Interval, errorBound: Double, format: FixedFormat)

/**
 * Range and error analysis of a graph, and the format rules: signed intervals for ranges, first-order plus
 * cross-term error propagation, every rounding counted. The one place that decides a node's fraction bits:
 *   - constants: `constantFracBits`, rounded to nearest; inputs: their own; sin/cos: the CORDIC output's;
 *   - add, subtract, negate: the larger of the operands' (exact, no rounding);
 *   - multiply: the operands' sum, capped at `internalFracBits` by `productRounding`;
 *   - a constant or product with a cap in `limits` (chosen by the target-error fit) at most that;
 *   - outputs: `outputFracBits`, rounded half up.
 * Integer bits follow from range + error, so no node can overflow; the model checks every value.
 */
final class Analysis(
    val graph: Graph,
    val numerics: Numerics,
    val hints: RangeHints = RangeHints.none,
    val limits: FracBitLimits = FracBitLimits.none
) {
  import Op._
  private val n = numerics

  /** Error of sin/cos of `angle`: the CORDIC unit's, plus half a code of each input angle in the sum. */
  def trigError(angle: AngleSum): Double = n.cordic.errorBound + angle.weight * n.angleError

  /**
   * The product rule, in one place for the analysis, the model, the schedule and the hardware: a multiply
   * keeps the operands' fraction bits up to `internalFracBits` (or its own cap in `limits`) and drops the
   * rest with `productRounding`; when it drops nothing it is exact (no rounding, no rounding register).
   */
  def productRounding(id: NodeId): ProductRounding = {
    val Mul(a, b) = graph(id): @unchecked
    rule(id, apply(a).format.fracBits, apply(b).format.fracBits)
  }

  private def rule(id: NodeId, fa: Int, fb: Int): ProductRounding = {
    val keep = Seq(fa + fb, n.internalFracBits, limits(id).getOrElse(Int.MaxValue)).min
    ProductRounding(keep, fa + fb - keep, if (fa + fb > keep) n.productRounding else Rounding.Truncate)
  }

  /** Fraction bits of constant `id`: the kind's, or its cap. */
  private def constantFracBits(id: NodeId): Int =
    math.min(n.constantFracBits, limits(id).getOrElse(Int.MaxValue))

  val nodes: IndexedSeq[NodeNumerics] = graph.ids.foldLeft(Vector.empty[NodeNumerics]) { (done, id) =>
    done :+ hinted(id, plain(id, x => done(x.index)))
  }

  /**
   * A node's interval intersected with its hint (both sound), its format recomputed for the tighter range.
   */
  private def hinted(id: NodeId, n: NodeNumerics): NodeNumerics = hints(id) match {
    case Some(h) if h < n.range.maxAbs && n.raw.isEmpty =>
      val range = Interval(math.max(n.range.lo, -h), math.min(n.range.hi, h))
      n.copy(range = range, format = FixedFormat.forRange(range.maxAbs + n.error, n.format.fracBits))
    case _ => n
  }

  private def plain(id: NodeId, at: NodeId => NodeNumerics): NodeNumerics =
    graph(id) match {
      case Const(v) =>
        val frac = constantFracBits(id)
        val raw = FixedFormat(62, frac).quantize(v, Rounding.HalfUp)
        NodeNumerics(
          Interval.point(v),
          math.abs(v - FixedFormat.scaleDown(raw, frac)),
          FixedFormat.forRawRange(raw.abs, frac),
          Some(raw)
        )
      case Input(s) if s.joint >= n.joints =>
        throw new IllegalArgumentException(s"graph input $s names a joint beyond the ${n.joints} declared")
      case Input(Signal.Velocity(j)) =>
        NodeNumerics(
          Interval.symmetric(n.velocityLimits(j)),
          0.5 * n.velocityFormats(j).lsb,
          n.velocityFormats(j)
        )
      case Input(Signal.Acceleration(j)) =>
        NodeNumerics(
          Interval.symmetric(n.accelerationLimits(j)),
          0.5 * n.accelerationFormats(j).lsb,
          n.accelerationFormats(j)
        )
      case Input(s: Signal.Parameter) =>
        val f = n.parameterFormats.getOrElse(
          s,
          throw new IllegalArgumentException(s"graph input $s has no declared range")
        )
        NodeNumerics(n.parameterRanges(s), 0.5 * f.lsb, f)
      case Trig(_, angle) => NodeNumerics(Interval(-1, 1), trigError(angle), n.cordic.outputFormat)
      case Add(a, b) =>
        rotated(a, b, isSum = true, at).getOrElse(
          exact(at(a).range + at(b).range, at(a).error + at(b).error, at(a), at(b))
        )
      case Sub(a, b) =>
        rotated(a, b, isSum = false, at).getOrElse(
          exact(at(a).range - at(b).range, at(a).error + at(b).error, at(a), at(b))
        )
      case Neg(a) => exact(-at(a).range, at(a).error, at(a), at(a))
      case Mul(a, b) =>
        val (x, y) = (at(a), at(b))
        val range = if (a == b) x.range.squared else x.range * y.range
        val dropped = rule(id, x.format.fracBits, y.format.fracBits)
        val error =
          x.range.maxAbs * y.error + x.error * y.range.maxAbs + x.error * y.error + dropped.errorBound
        NodeNumerics(range, error, FixedFormat.forRange(range.maxAbs + error, dropped.keep))
    }

  /**
   * `cos(a) u +- sin(a) w`, the shape every rotation by a joint angle takes once folded: by Cauchy-Schwarz
   * with cos^2 + sin^2 = 1, |value| <= hypot(|u|, |w|) and the error of u and w enters as hypot(e_u, e_w),
   * where intervals would add them. Without this, ranges and errors grow by up to 2x per joint down the
   * chain. None when the node does not have that shape.
   *
   * A factor may be a constant times the sin/cos, `(k cos(a)) u` (products reassociated, [[Reassociate]]):
   * the same argument with k u in place of u bounds the value by hypot(|k| |u|, |k'| |w|); the computed
   * factor's error e_c (the constant's, the sin/cos's and the rounding of k cos(a)) enters as e_c |u'|, as
   * the sin/cos's own error does for a plain factor.
   */
  private def rotated(
      a: NodeId,
      b: NodeId,
      isSum: Boolean,
      at: NodeId => NodeNumerics
  ): Option[NodeNumerics] =
    Rotation.terms(graph, a, b) match {
      case Some((p, q)) =>
        val (nu, nw) = (at(p.u), at(q.u))
        def roundingOf(m: NodeId) = {
          val Mul(x, y) = graph(m): @unchecked
          rule(m, at(x).format.fracBits, at(y).format.fracBits).errorBound
        }
        // |k|, and the error of the computed factor k cos(q) (the sin/cos's own for a plain factor).
        def scale(t: Rotation.Term) = t.scale.fold(1.0)(math.abs)
        def factorError(t: Rotation.Term) = if (t.scale.isEmpty) trigError(t.angle) else at(t.factor).error
        val bound = math.hypot(scale(p) * nu.range.maxAbs, scale(q) * nw.range.maxAbs)
        val error =
          math.hypot(scale(p) * nu.error, scale(q) * nw.error) + factorError(p) * nu.computedMaxAbs +
            factorError(q) * nw.computedMaxAbs + roundingOf(a) + roundingOf(b)
        // Both bounds are sound: keep the tighter of each.
        val plain = exact(
          if (isSum) at(a).range + at(b).range else at(a).range - at(b).range,
          at(a).error + at(b).error,
          at(a),
          at(b)
        )
        val range = Interval(math.max(plain.range.lo, -bound), math.min(plain.range.hi, bound))
        val e = math.min(error, plain.error)
        Some(NodeNumerics(range, e, FixedFormat.forRange(range.maxAbs + e, plain.format.fracBits)))
      case _ => None
    }

  private def exact(range: Interval, error: Double, a: NodeNumerics, b: NodeNumerics): NodeNumerics = {
    val frac = math.max(a.format.fracBits, b.format.fracBits)
    NodeNumerics(range, error, FixedFormat.forRange(range.maxAbs + error, frac))
  }

  def apply(id: NodeId): NodeNumerics = nodes(id.index)

  /** Bits an output drops to reach `outputFracBits` (rounded half up); negative: bits it gains (exact). */
  def outputDrop(o: Output): Int = apply(o.node).format.fracBits - n.outputFracBits

  val outputs: IndexedSeq[OutputNumerics] = graph.outputs.map { o =>
    val node = apply(o.node)
    val drop = outputDrop(o)
    val error =
      node.error + (if (drop > 0) Rounding.maxErrorLsb(Rounding.HalfUp) * math.pow(2.0, -n.outputFracBits)
                    else 0.0)
    OutputNumerics(
      o.name,
      node.range,
      error,
      FixedFormat.forRange(node.range.maxAbs + error, n.outputFracBits)
    )
  }

  /** Every output in one port format: the widest. */
  val outputPortFormat: FixedFormat = outputs.map(_.format).maxBy(_.width)

  outputs.foreach(o =>
    require(
      o.format.width <= 64,
      s"output ${o.name} needs ${o.format.width} bits; narrow the declared ranges"
    )
  )

  /** The widest node, for reports. */
  def widest: (NodeId, NodeNumerics) = graph.ids.map(id => id -> apply(id)).maxBy(_._2.format.width)
}
