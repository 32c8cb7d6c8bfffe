package reducerload.graph

import reducerload.load.TimedArith

/**
 * As-soon-as-possible schedule of a graph, one operator per operation (one sample per clock):
 * the cycle at which each node's value of the current sample is in a register (None: a constant).
 * The hardware builds exactly this schedule and balances every operand to it; the latency below is
 * the one the RTL tests observe.
 *
 * @param inputCycle cycle at which the clamped velocities and accelerations are in registers
 * @param trigCycle  cycle at which sin/cos of every angle leave the CORDIC units
 */
final class Schedule(analysis: Analysis, val inputCycle: Int, val trigCycle: Int, multiplierLatency: Int) {
  import Op._
  private val graph = analysis.graph

  /** Clocks of a multiply of these operands: the pipelined multiplier, extra registers, and a rounding adder when it rounds half up. */
  def mulLatency(a: NodeId, b: NodeId): Int = {
    val (fa, fb) = (analysis(a).format, analysis(b).format)
    TimedArith.mulLatency(fa.width, fb.width, multiplierLatency, analysis.productRounding(fa.fracBits, fb.fracBits).rounding)
  }

  val ready: IndexedSeq[Option[Int]] = graph.fold[Option[Int]] { (op, at) =>
    def meet(ids: NodeId*) = ids.flatMap(at(_)).maxOption.getOrElse(0)
    op match {
      case Const(_)  => None
      case Input(_)  => Some(inputCycle)
      case Trig(_, _) => Some(trigCycle)
      case Add(a, b) => Some(meet(a, b) + 1)
      case Sub(a, b) => Some(meet(a, b) + 1)
      case Neg(a)    => Some(meet(a) + 1)
      case Mul(a, b) => Some(meet(a, b) + mulLatency(a, b))
    }
  }

  def apply(id: NodeId): Option[Int] = ready(id.index)

  /** Cycle at which every output is in its register (before the output stage). */
  val outputsReady: Int = graph.outputs.flatMap(o => apply(o.node)).maxOption.getOrElse(inputCycle)

  /** Cycles from a sample on the input port to its torques on the output port (output stage included). */
  val latency: Int = outputsReady + 1
}
