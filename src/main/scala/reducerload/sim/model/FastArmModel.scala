package reducerload.sim.model

import reducerload.arm.{ArmOutputCodes, ArmParams}
import reducerload.fixedpoint.{FixedFormat, Rounding}
import reducerload.graph.{NodeId, Op, SampleCodes, Signal, TrigFn}

import scala.collection.immutable.ArraySeq

/**
 * [[reducerload.arm.ArmModel.evaluate]] in long arithmetic: the same graph, the same operations in the same
 * order, every value checked against the same proven format, compiled once into arrays so a sample costs no
 * allocation per node (a replay of millions of samples). Only for designs whose formats all fit 62 bits
 * ([[FastArmModel.supports]]); tested equal to the model (FastFixedSpec).
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
      case Op.Const(_)                  => kind(i) = Constant; constant(i) = analysis.nodes(i).raw.get.toLong
      case Op.Input(Signal.Velocity(j)) => kind(i) = Velocity; left(i) = j
      case Op.Input(Signal.Acceleration(j)) => kind(i) = Acceleration; left(i) = j
      case Op.Input(s: Signal.Parameter)    => kind(i) = Parameter; left(i) = numerics.parameters.indexOf(s)
      case Op.Trig(fn, a) =>
        kind(i) = Trig; left(i) = 2 * angles.indexOf(a) + (if (fn == TrigFn.Cos) 0 else 1)
      case Op.Add(a, b) =>
        kind(i) = Add; left(i) = a.index; right(i) = b.index; leftShift(i) = f - fr(a.index);
        rightShift(i) = f - fr(b.index)
      case Op.Sub(a, b) =>
        kind(i) = Sub; left(i) = a.index; right(i) = b.index; leftShift(i) = f - fr(a.index);
        rightShift(i) = f - fr(b.index)
      case Op.Neg(a) => kind(i) = Neg; left(i) = a.index
      case Op.Mul(a, b) =>
        val rule = analysis.productRounding(NodeId(i))
        kind(i) = Mul; left(i) = a.index; right(i) = b.index; drop(i) = rule.drop; rounding(i) = rule.rounding
    }
  }

  private val velocityLimit = numerics.velocityLimitRaw.map(_.toLong).toArray
  private val accelerationLimit = numerics.accelerationLimitRaw.map(_.toLong).toArray
  private val outputs = graph.outputs
    .zip(analysis.outputs)
    .map { case (o, info) =>
      (o.node.index, analysis.outputDrop(o), FastFixed.minOf(info.format), FastFixed.maxOf(info.format))
    }
    .toArray
  private val joints = velocityLimit.length
  private val parameterLow = numerics.parameters.map(numerics.parameterLimitRaw(_)._1.toLong).toArray
  private val parameterHigh = numerics.parameters.map(numerics.parameterLimitRaw(_)._2.toLong).toArray

  /** Torque codes per sample (the graph's outputs); then come [[joints]] out-of-range flags. */
  val torques: Int = outputs.length

  /**
   * Codes per sample in and values out of [[Runner.evaluate]], in the harness ports' order: angles,
   * velocities, accelerations, then the run-time parameters (the payload) in `numerics.parameters`' order.
   */
  val inputCount: Int = 3 * joints + parameterLow.length
  val outputCount: Int = torques + joints

  def evaluate(in: SampleCodes): ArmOutputCodes = {
    def long(x: BigInt): Long = { require(x.isValidLong, s"input code $x does not fit 64 bits"); x.toLong }
    val codes = (in.angles ++ in.velocities ++ in.accelerations ++ numerics.parameters.map(in.parameters))
      .map(long)
      .toArray
    require(codes.length == inputCount, s"FastArmModel: ${codes.length} input codes for $joints joints")
    val out = new Array[Long](outputCount)
    runner().evaluate(codes, 0, out, 0)
    ArmOutputCodes(
      ArraySeq.unsafeWrapArray(out.take(torques).map(BigInt(_))),
      ArraySeq.unsafeWrapArray(out.drop(torques).map(_ != 0))
    )
  }

  /** Work arrays for [[Runner.evaluate]]; one per thread. */
  def runner(): Runner = new Runner

  final class Runner private[FastArmModel] () {
    private val qd = new Array[Long](joints)
    private val qdd = new Array[Long](joints)
    private val flags = new Array[Boolean](joints)
    private val parameter = new Array[Long](FastArmModel.this.parameterLow.length)
    private val trig = new Array[Long](2 * angles.size)
    private val v = new Array[Long](size)
    private val (kind, left, right, leftShift, rightShift, drop) = (
      FastArmModel.this.kind,
      FastArmModel.this.left,
      FastArmModel.this.right,
      FastArmModel.this.leftShift,
      FastArmModel.this.rightShift,
      FastArmModel.this.drop
    )
    private val halfUp = rounding.map(_ == Rounding.HalfUp)
    private val (constant, lo, hi) = (FastArmModel.this.constant, FastArmModel.this.lo, FastArmModel.this.hi)
    private val (angleJoints, angleMultiples, turnMask) =
      (FastArmModel.this.angleJoints, FastArmModel.this.angleMultiples, FastArmModel.this.turnMask)
    private val (velocityLimit, accelerationLimit) =
      (FastArmModel.this.velocityLimit, FastArmModel.this.accelerationLimit)
    private val (parameterLow, parameterHigh) =
      (FastArmModel.this.parameterLow, FastArmModel.this.parameterHigh)
    private val outNode = outputs.map(_._1)
    private val outDrop = outputs.map(_._2)
    private val outMin = outputs.map(_._3)
    private val outMax = outputs.map(_._4)

    /**
     * One sample: `codes(at ..)` holds the angle, velocity and acceleration codes (one per joint each);
     * writes the torque codes and then each joint's out-of-range flag (0 or 1) to `out(outAt ..)`.
     */
    def evaluate(codes: Array[Long], at: Int, out: Array[Long], outAt: Int): Unit = {
      // Locals: scalac's -Xcheckinit guards every field read.
      val qd = this.qd; val qdd = this.qdd; val flags = this.flags; val trig = this.trig
      val kind = this.kind; val left = this.left; val right = this.right; val leftShift = this.leftShift
      val rightShift = this.rightShift; val drop = this.drop; val halfUp = this.halfUp;
      val constant = this.constant
      val lo = this.lo; val hi = this.hi; val velocityLimit = this.velocityLimit;
      val accelerationLimit = this.accelerationLimit
      val angleJoints = this.angleJoints; val angleMultiples = this.angleMultiples;
      val turnMask = this.turnMask
      val outNode = this.outNode; val outDrop = this.outDrop; val outMin = this.outMin;
      val outMax = this.outMax
      val parameter = this.parameter; val parameterLow = this.parameterLow;
      val parameterHigh = this.parameterHigh
      val n = qd.length
      var j = 0
      while (j < n) {
        val x = codes(at + n + j)
        val l = velocityLimit(j)
        flags(j) = x > l || x < -l
        qd(j) = if (x > l) l else if (x < -l) -l else x
        val y = codes(at + 2 * n + j)
        val m = accelerationLimit(j)
        if (y > m || y < -m) flags(j) = true
        qdd(j) = if (y > m) m else if (y < -m) -m else y
        j += 1
      }
      // A clamped payload parameter changes every torque: it flags every joint.
      var parameterOutside = false
      var p = 0
      while (p < parameter.length) {
        val x = codes(at + 3 * n + p)
        if (x < parameterLow(p) || x > parameterHigh(p)) parameterOutside = true
        parameter(p) =
          if (x < parameterLow(p)) parameterLow(p) else if (x > parameterHigh(p)) parameterHigh(p) else x
        p += 1
      }
      var a = 0
      while (a < angleJoints.length) {
        val js = angleJoints(a)
        val ks = angleMultiples(a)
        var code = 0L
        var t = 0
        while (t < js.length) { code += ks(t) * codes(at + js(t)); t += 1 }
        cordic.sinCosRaw(code & turnMask, trig, 2 * a) // binary angles wrap modulo one turn
        a += 1
      }
      val v = this.v
      var i = 0
      while (i < v.length) {
        val x = (kind(i): @annotation.switch) match {
          case Constant     => constant(i)
          case Velocity     => qd(left(i))
          case Acceleration => qdd(left(i))
          case Parameter    => parameter(left(i))
          case Trig         => trig(left(i))
          case Add          => (v(left(i)) << leftShift(i)) + (v(right(i)) << rightShift(i))
          case Sub          => (v(left(i)) << leftShift(i)) - (v(right(i)) << rightShift(i))
          case Neg          => -v(left(i))
          case _ =>
            FastFixed.mulShiftRound(
              v(left(i)),
              v(right(i)),
              drop(i),
              if (halfUp(i)) Rounding.HalfUp else Rounding.Truncate
            )
        }
        if (x < lo(i) || x > hi(i))
          throw new IllegalArgumentException(
            s"GraphModel: node $i (${graph.ops(i)}) = $x outside its proven format ${analysis.nodes(i).format}"
          )
        v(i) = x
        i += 1
      }
      var saturated = parameterOutside
      var k = 0
      while (k < outNode.length) {
        val d = outDrop(k)
        val r = if (d >= 0) FastFixed.shiftRound(v(outNode(k)), d, Rounding.HalfUp) else v(outNode(k)) << -d
        if (r < outMin(k) || r > outMax(k)) saturated = true
        out(outAt + k) = if (r < outMin(k)) outMin(k) else if (r > outMax(k)) outMax(k) else r
        k += 1
      }
      j = 0
      while (j < n) { out(outAt + outNode.length + j) = if (flags(j) || saturated) 1L else 0L; j += 1 }
    }
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
  private final val Parameter = 8

  /**
   * Whether the long model can run `p`: every node, port and CORDIC format fits 62 bits, and the output
   * shifts stay in range.
   */
  def supports(p: ArmParams): Boolean =
    scala.util.Try { new FastCordic(p.numerics.cordic); () }.isSuccess &&
      (p.analysis.nodes.map(_.format) ++ p.analysis.outputs.map(_.format) ++
        Seq(p.numerics.velocityPortFormat, p.numerics.accelerationPortFormat) ++
        p.numerics.parameterFormats.values).forall((f: FixedFormat) => f.width <= 62) &&
      p.graph.outputs.forall(o => p.analysis.outputDrop(o) > -62)
}
