package reducerload.sim

import reducerload.arm.{ArmOutputCodes, ArmParams}
import reducerload.fixedpoint.{FixedFormat, Rounding}
import reducerload.graph.{NodeId, Op, SampleCodes, Signal, TrigFn}

import scala.collection.immutable.ArraySeq

/**
 * [[reducerload.arm.ArmModel.evaluate]] in long arithmetic: the same graph, the same operations in
 * the same order, every value checked against the same proven format, compiled once into arrays so
 * a sample costs no allocation per node (a replay of millions of samples). Only for designs whose
 * formats all fit 62 bits ([[FastArmModel.supports]]); tested equal to the model (FastFixedSpec).
 */
final class FastArmModel(p: ArmParams) {
  import FastArmModel._
  private val analysis = p.analysis
  private val graph = p.graph
  private val numerics = p.numerics
  private val cordic = new FastCordic(numerics.cordic)
  private val turnMask = (1L << numerics.angleBits) - 1
  private val size = graph.ops.size
  private def fr(i: Int) = analysis.nodes(i).format.fracBits

  // One entry per node: what it does, its operands, the shifts that align them, its format's limits.
  private val kind = new Array[Int](size)
  private val left = new Array[Int](size)
  private val right = new Array[Int](size)
  private val leftShift = new Array[Int](size)
  private val rightShift = new Array[Int](size)
  private val drop = new Array[Int](size)
  private val rounding = new Array[Rounding](size)
  private val constant = new Array[Long](size)
  private val lo = analysis.nodes.map(n => FastFixed.minOf(n.format)).toArray
  private val hi = analysis.nodes.map(n => FastFixed.maxOf(n.format)).toArray

  /** Each distinct angle sum: its joints and multiples, and where its cos and sin go in `trig`. */
  private val angles = graph.angles.toIndexedSeq
  private val angleJoints = angles.map(_.terms.map(_._1).toArray).toArray
  private val angleMultiples = angles.map(_.terms.map(_._2.toLong).toArray).toArray

  graph.ops.zipWithIndex.foreach { case (op, i) =>
    val f = fr(i)
    op match {
      case Op.Const(_)                      => kind(i) = Constant; constant(i) = analysis.nodes(i).raw.get.toLong
      case Op.Input(Signal.Velocity(j))     => kind(i) = Velocity; left(i) = j
      case Op.Input(Signal.Acceleration(j)) => kind(i) = Acceleration; left(i) = j
      case Op.Trig(fn, a)                   => kind(i) = Trig; left(i) = 2 * angles.indexOf(a) + (if (fn == TrigFn.Cos) 0 else 1)
      case Op.Add(a, b) => kind(i) = Add; left(i) = a.index; right(i) = b.index; leftShift(i) = f - fr(a.index); rightShift(i) = f - fr(b.index)
      case Op.Sub(a, b) => kind(i) = Sub; left(i) = a.index; right(i) = b.index; leftShift(i) = f - fr(a.index); rightShift(i) = f - fr(b.index)
      case Op.Neg(a)    => kind(i) = Neg; left(i) = a.index
      case Op.Mul(a, b) =>
        val rule = analysis.productRounding(NodeId(i))
        kind(i) = Mul; left(i) = a.index; right(i) = b.index; drop(i) = rule.drop; rounding(i) = rule.rounding
    }
  }

  private val velocityLimit = numerics.velocityLimitRaw.map(_.toLong).toArray
  private val accelerationLimit = numerics.accelerationLimitRaw.map(_.toLong).toArray
  private val outputs = graph.outputs.zip(analysis.outputs).map { case (o, info) =>
    (o.node.index, analysis.outputDrop(o), FastFixed.minOf(info.format), FastFixed.maxOf(info.format))
  }.toArray
  private val joints = velocityLimit.length

  def evaluate(in: SampleCodes): ArmOutputCodes = {
    val flags = new Array[Boolean](joints)
    def clamp(x: BigInt, limit: Long, j: Int): Long = {
      require(x.isValidLong, s"input code $x does not fit 64 bits")
      val v = x.toLong
      if (v > limit) { flags(j) = true; limit } else if (v < -limit) { flags(j) = true; -limit } else v
    }
    val qd = Array.tabulate(joints)(j => clamp(in.velocities(j), velocityLimit(j), j))
    val qdd = Array.tabulate(joints)(j => clamp(in.accelerations(j), accelerationLimit(j), j))
    val trig = new Array[Long](2 * angles.size)
    var a = 0
    while (a < angles.size) {
      val js = angleJoints(a)
      var code = 0L
      var t = 0
      while (t < js.length) { code += angleMultiples(a)(t) * in.angles(js(t)).toLong; t += 1 }
      cordic.sinCosRaw(code & turnMask, trig, 2 * a) // binary angles wrap modulo one turn
      a += 1
    }
    val v = new Array[Long](size)
    var i = 0
    while (i < size) {
      val x = kind(i) match {
        case Constant     => constant(i)
        case Velocity     => qd(left(i))
        case Acceleration => qdd(left(i))
        case Trig         => trig(left(i))
        case Add          => (v(left(i)) << leftShift(i)) + (v(right(i)) << rightShift(i))
        case Sub          => (v(left(i)) << leftShift(i)) - (v(right(i)) << rightShift(i))
        case Neg          => -v(left(i))
        case _            => FastFixed.mulShiftRound(v(left(i)), v(right(i)), drop(i), rounding(i))
      }
      if (x < lo(i) || x > hi(i))
        throw new IllegalArgumentException(s"GraphModel: node $i (${graph.ops(i)}) = $x outside its proven format ${analysis.nodes(i).format}")
      v(i) = x
      i += 1
    }
    val codes = outputs.map { case (node, outDrop, min, max) =>
      val r = if (outDrop >= 0) FastFixed.shiftRound(v(node), outDrop, Rounding.HalfUp) else v(node) << -outDrop
      (r.max(min).min(max), r < min || r > max)
    }
    val saturated = codes.exists(_._2)
    ArmOutputCodes(ArraySeq.unsafeWrapArray(codes.map(c => BigInt(c._1))), ArraySeq.unsafeWrapArray(flags.map(_ || saturated)))
  }
}

object FastArmModel {
  private final val Constant = 0
  private final val Velocity = 1
  private final val Acceleration = 2
  private final val Trig = 3
  private final val Add = 4
  private final val Sub = 5
  private final val Neg = 6
  private final val Mul = 7

  /** Whether the long model can run `p`: every node, port and CORDIC format fits 62 bits, and the output shifts stay in range. */
  def supports(p: ArmParams): Boolean =
    scala.util.Try { new FastCordic(p.numerics.cordic); () }.isSuccess &&
      (p.analysis.nodes.map(_.format) ++ p.analysis.outputs.map(_.format) ++
        Seq(p.numerics.velocityPortFormat, p.numerics.accelerationPortFormat)).forall((f: FixedFormat) => f.width <= 62) &&
      p.graph.outputs.forall(o => p.analysis.outputDrop(o) > -62)
}
