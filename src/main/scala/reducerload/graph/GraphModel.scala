package reducerload.graph

import reducerload.cordic.CordicModel
import reducerload.fixedpoint.{FixedFormat, Rounding}

/**
 * One sample as the datapath sees it: binary angles and the (clamped) velocity and acceleration codes per
 * joint, and the codes of the run-time inertial parameters it is computed with (the payload).
 */
final case class SampleCodes(
    angles: IndexedSeq[BigInt],
    velocities: IndexedSeq[BigInt],
    accelerations: IndexedSeq[BigInt],
    parameters: Map[Signal.Parameter, BigInt] = Map.empty
)

/**
 * Bit-accurate integer interpretation of a graph under its [[Analysis]]: the exact integer operations the
 * hardware performs, every value checked against its proven format.
 */
final class GraphModel(val analysis: Analysis) {
  import Op._
  private val graph = analysis.graph
  private val cordic = new CordicModel(analysis.numerics.cordic)
  private val turn = BigInt(1) << analysis.numerics.angleBits

  /** Align `raw` from `from` to `to` fraction bits (gaining bits only: exact). */
  private def align(raw: BigInt, from: Int, to: Int): BigInt = {
    require(to >= from, s"GraphModel: cannot align $from to $to fraction bits without rounding")
    raw << (to - from)
  }

  /** Binary angle code of an angle sum (wraps modulo one turn). */
  def angleCode(angle: AngleSum, codes: IndexedSeq[BigInt]): BigInt =
    angle.terms.map { case (j, k) => codes(j) * k }.sum.mod(turn)

  /** Every node's raw value for one sample (inputs already clamped to their declared ranges). */
  def nodeValues(s: SampleCodes): IndexedSeq[BigInt] = {
    val trig = graph.angles.map(a => a -> cordic.sinCosRaw(angleCode(a, s.angles))).toMap
    graph.ids.foldLeft(Vector.empty[BigInt]) { (done, id) =>
      val f = analysis(id).format
      def fr(x: NodeId) = analysis(x).format.fracBits
      val v = graph(id) match {
        case Const(_)                      => analysis(id).raw.get
        case Input(Signal.Velocity(j))     => s.velocities(j)
        case Input(Signal.Acceleration(j)) => s.accelerations(j)
        case Input(p: Signal.Parameter)    => s.parameters(p)
        case Trig(TrigFn.Cos, a)           => trig(a)._1
        case Trig(TrigFn.Sin, a)           => trig(a)._2
        case Add(a, b) => align(done(a.index), fr(a), f.fracBits) + align(done(b.index), fr(b), f.fracBits)
        case Sub(a, b) => align(done(a.index), fr(a), f.fracBits) - align(done(b.index), fr(b), f.fracBits)
        case Neg(a)    => -done(a.index)
        case Mul(a, b) =>
          val rule = analysis.productRounding(id)
          FixedFormat.shiftRound(done(a.index) * done(b.index), rule.drop, rule.rounding)
      }
      require(f.contains(v), s"GraphModel: node ${id.index} (${graph(id)}) = $v outside its proven format $f")
      done :+ v
    }
  }

  /** Output codes (in the output port format) and whether each saturated (never, by the range proof). */
  def outputs(s: SampleCodes): IndexedSeq[(BigInt, Boolean)] = {
    val values = nodeValues(s)
    graph.outputs.zip(analysis.outputs).map { case (o, info) =>
      FixedFormat.saturate(GraphModel.toOutput(values(o.node.index), analysis.outputDrop(o)), info.format)
    }
  }
}

object GraphModel {

  /** The output stage: drop bits half up, or gain them exactly. */
  def toOutput(raw: BigInt, drop: Int): BigInt = FixedFormat.rescale(raw, drop, Rounding.HalfUp)
}
