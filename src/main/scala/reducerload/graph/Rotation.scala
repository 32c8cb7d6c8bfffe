package reducerload.graph

/**
 * The shape every rotation by a joint angle takes once folded, `cos(q) u +- sin(q) w`, which [[Analysis]]
 * bounds by hypot and [[Reassociate]] keeps as one term. A factor may also be a constant times the sin/cos,
 * `(k cos(q)) u`, the shape constants pushed into a rotation take ([[Reassociate.distributeConstants]]).
 */
object Rotation {
  import Op._

  /**
   * A product's rotation factor: `factor` is the sin/cos, or the constant `scale` times it; `u` the other
   * operand.
   */
  final case class Term(fn: TrigFn, angle: AngleSum, factor: NodeId, scale: Option[Double], u: NodeId)

  /** Product `m` as a rotation term, if it has that shape. */
  def term(graph: Graph, m: NodeId): Option[Term] = {
    def factor(c: NodeId, u: NodeId): Option[Term] = graph(c) match {
      case Trig(fn, angle) => Some(Term(fn, angle, c, None, u))
      case Mul(x, y) =>
        (graph(x), graph(y)) match {
          case (Const(k), Trig(fn, angle)) => Some(Term(fn, angle, c, Some(k), u))
          case (Trig(fn, angle), Const(k)) => Some(Term(fn, angle, c, Some(k), u))
          case _                           => None
        }
      case _ => None
    }
    graph(m) match {
      case Mul(x, y) => factor(x, y).orElse(factor(y, x))
      case _         => None
    }
  }

  /** The two rotation terms of `a +- b`, when they rotate by one angle. */
  def terms(graph: Graph, a: NodeId, b: NodeId): Option[(Term, Term)] =
    (term(graph, a), term(graph, b)) match {
      case (Some(p), Some(q)) if p.angle == q.angle && p.fn != q.fn => Some((p, q))
      case _                                                        => None
    }

  /** Whether sum node `s` is a rotation. */
  def isRotation(graph: Graph, s: NodeId): Boolean = graph(s) match {
    case Add(a, b) => terms(graph, a, b).isDefined
    case Sub(a, b) => terms(graph, a, b).isDefined
    case _         => false
  }
}
