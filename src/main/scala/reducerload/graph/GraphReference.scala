package reducerload.graph

/** Double-precision interpretation of a graph: what the fixed-point datapath approximates. */
object GraphReference {
  import Op._

  /**
   * Outputs for angles `q` (rad), velocities `qd` and accelerations `qdd`, one each per joint, and the
   * run-time inertial parameters' values (SI units).
   */
  def outputs(
      graph: Graph,
      q: Seq[Double],
      qd: Seq[Double],
      qdd: Seq[Double],
      parameters: Map[Signal.Parameter, Double] = Map.empty
  ): IndexedSeq[Double] = {
    val values = graph.fold[Double] { (op, at) =>
      op match {
        case Const(v)                      => v
        case Input(Signal.Velocity(j))     => qd(j)
        case Input(Signal.Acceleration(j)) => qdd(j)
        case Input(p: Signal.Parameter)    => parameters(p)
        case Trig(fn, angle) =>
          TrigFn.reference(fn, angle.radians(q))
        case Add(a, b) => at(a) + at(b)
        case Sub(a, b) => at(a) - at(b)
        case Neg(a)    => -at(a)
        case Mul(a, b) => at(a) * at(b)
      }
    }
    graph.outputs.map(o => values(o.node.index))
  }
}
