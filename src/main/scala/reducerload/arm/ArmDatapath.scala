package reducerload.arm

import chisel3._
import chisel3.util._
import reducerload.cordic.CordicSinCos
import reducerload.fixedpoint.{FixedHw, Rounding}
import reducerload.graph._
import reducerload.load.Timed
import reducerload.pipeline.PipelinedMultiplier

/**
 * Every joint torque of a serial arm, one sample per clock: the hardware interpretation of the
 * graph in `p.graph`, one operator per operation, at the cycles of `p.schedule` (operands are
 * delayed to meet, long delays in block RAM). A sample enters on `io.in` (always ready) and its
 * torques leave on `io.out` exactly `p.latency` cycles later.
 *
 * Cycle 1 registers the input; cycle 2 clamps each velocity and acceleration to its joint's
 * declared range (flagging the joint) and registers each angle sum, which enters a CORDIC unit
 * (one per distinct angle). Data registers have no reset; the valid chain does.
 */
class ArmDatapath(val p: ArmParams) extends Module {
  override def desiredName = s"ArmDatapath_${p.tag}"
  val io = IO(new Bundle {
    val in = Flipped(Decoupled(new ArmInput(p)))
    val out = Valid(new ArmOutput(p))
  })
  import Op._
  private val analysis = p.analysis
  private val schedule = p.schedule
  private val numerics = p.numerics
  private val joints = p.chain.size
  private def timed(v: SInt, at: Int) = Timed(v, Some(at), p.memoryDelayMinCycles)

  io.in.ready := true.B
  private val in = RegNext(io.in.bits)
  private val inValid = RegNext(io.in.valid, false.B)

  // Cycle 2: clamp to the declared ranges, in each joint's own format.
  private def clamp(x: SInt, limit: BigInt, width: Int): (SInt, Bool) = {
    val (value, outside) = FixedHw.clamp(x, -limit, limit, width)
    (FixedHw.delay(value, 1), RegNext(outside))
  }
  private val velocities = (0 until joints).map(j => clamp(in.qd(j), numerics.velocityLimitRaw(j), numerics.velocityFormats(j).width))
  private val accelerations = (0 until joints).map(j => clamp(in.qdd(j), numerics.accelerationLimitRaw(j), numerics.accelerationFormats(j).width))
  require(ArmDatapath.inputCycle == 2, "the input stage above is two registers deep")
  // Cycle 3: one flag per joint (the two compares were registered apart: they were the critical path).
  private val jointFlags = (0 until joints).map(j => RegNext(velocities(j)._2 || accelerations(j)._2))

  // Cycle 2: angle sums (binary angles wrap modulo one turn, as angles do), then one CORDIC unit each.
  private val sinCos = p.graph.angles.map { angle =>
    val sum = angle.terms.foldLeft(0.U(numerics.angleBits.W)) { case (acc, (j, k)) =>
      (0 until k.abs).foldLeft(acc)((a, _) => if (k > 0) a +% in.q(j) else a -% in.q(j))
    }
    val unit = Module(new CordicSinCos(p.cordic))
    unit.io.in.valid := RegNext(inValid, false.B)
    unit.io.in.bits := RegNext(sum)
    angle -> unit.io.out.bits
  }.toMap

  // The graph, node by node, each value registered at the cycle the schedule gives it.
  private val values: Vector[Timed] = p.graph.ids.foldLeft(Vector.empty[Timed]) { (done, id) =>
    val f = analysis(id).format
    def operand(x: NodeId) = done(x.index)
    def cycleOf(ids: NodeId*) = ids.flatMap(x => done(x.index).at).maxOption.getOrElse(0)
    /** Operand `x` at cycle `t`, its fraction bits raised to `f`'s, sign-extended to `f`'s width. */
    def aligned(x: NodeId, t: Int): SInt = {
      val v = operand(x).alignedTo(t)
      (v << (f.fracBits - analysis(x).format.fracBits)).asSInt.pad(f.width)
    }
    // Proven range: any top bits dropped here only repeat the sign.
    def fit(v: SInt): SInt = if (v.getWidth >= f.width) v(f.width - 1, 0).asSInt else v.pad(f.width)
    def registered(v: SInt, t: Int) = timed(FixedHw.delay(fit(v), 1), t + 1)
    val value = p.graph(id) match {
      case Const(_) => Timed(analysis(id).raw.get.S(f.width.W), None)
      case Input(Signal.Velocity(j)) => timed(velocities(j)._1, ArmDatapath.inputCycle)
      case Input(Signal.Acceleration(j)) => timed(accelerations(j)._1, ArmDatapath.inputCycle)
      case Trig(TrigFn.Cos, a) => timed(sinCos(a).cos, schedule.trigCycle)
      case Trig(TrigFn.Sin, a) => timed(sinCos(a).sin, schedule.trigCycle)
      case Add(a, b) => val t = cycleOf(a, b); registered(aligned(a, t) + aligned(b, t), t)
      case Sub(a, b) => val t = cycleOf(a, b); registered(aligned(a, t) - aligned(b, t), t)
      case Neg(a)    => val t = cycleOf(a); registered(-aligned(a, t), t)
      case Mul(a, b) =>
        val t = cycleOf(a, b)
        val rule = analysis.productRounding(analysis(a).format.fracBits, analysis(b).format.fracBits)
        val product = FixedHw.delay(PipelinedMultiplier(operand(a).alignedTo(t), operand(b).alignedTo(t)), p.multiplierLatency - 1)
        val fitted = fit(FixedHw.shiftRound(product, rule.drop, rule.rounding))
        val done = t + schedule.mulLatency(a, b)
        if (rule.rounding == Rounding.Truncate) timed(fitted, done) else timed(FixedHw.delay(fitted, 1), done)
    }
    require(value.at == schedule(id), s"ArmDatapath: node ${id.index} built at ${value.at}, scheduled at ${schedule(id)}")
    done :+ value
  }

  // Output stage: every torque at one cycle, rounded half up to the output format, then registered.
  private val outAt = schedule.outputsReady
  private val results = p.graph.outputs.zip(analysis.outputs).map { case (o, info) =>
    val v = values(o.node.index).alignedTo(outAt)
    val drop = analysis.outputDrop(o)
    val rounded = FixedHw.rescale(v, drop, Rounding.HalfUp)
    val (code, saturated) = FixedHw.saturate(rounded, info.format)
    (code.pad(analysis.outputPortFormat.width), saturated)
  }
  private val anySaturated = results.map(_._2).reduce(_ || _)
  private val outBits = Reg(new ArmOutput(p))
  outBits.tau := VecInit(results.map(_._1))
  outBits.outOfRange := VecInit(jointFlags.map(f => FixedHw.delay(f, outAt - ArmDatapath.flagCycle) || anySaturated))
  io.out.bits := outBits
  io.out.valid := ShiftRegister(inValid, p.latency - 1, false.B, true.B)
}

object ArmDatapath {

  /** Cycle at which the clamped velocities and accelerations and the angle sums are in registers. */
  val inputCycle: Int = 2

  /** Cycle at which each joint's out-of-range flag is in its register. */
  val flagCycle: Int = inputCycle + 1
}
