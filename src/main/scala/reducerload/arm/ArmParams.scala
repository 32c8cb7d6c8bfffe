package reducerload.arm

import reducerload.cordic.CordicParams
import reducerload.dynamics.{JointState, Rnea}
import reducerload.fixedpoint.Rounding
import reducerload.graph._
import reducerload.load.{Joint3Load, LoadModel, RobotParams}
import reducerload.robot.SerialChain

/** What a datapath computes from its chain's joint states: the graph's outputs. */
sealed abstract class Dynamics(val name: String, val description: String)
object Dynamics {

  /** Every joint torque by RNEA, one output per joint. */
  case object Rnea extends Dynamics("rnea", "every joint torque by RNEA")

  /** The planar arm's joint-3 load in closed form ([[reducerload.load.Joint3Load]]), one output. */
  final case class Joint3(model: LoadModel, robot: RobotParams)
      extends Dynamics(model.name, s"joint-3 load: ${model.description}") {
    require(model.closedForm, s"model ${model.name} is not a joint-3 closed form")
    require(robot.isPlanar3, s"the joint-3 closed forms are for the built-in planar3, not ${robot.source}")
  }
}

/**
 * Generator parameters of [[ArmDatapath]] for a serial arm: its torques (`dynamics`) as one expression graph
 * with the robot's constants folded. The joint count is the chain's; per-joint ranges must match it. Formats,
 * error bounds and the schedule are derived (see [[Analysis]]).
 *
 * @param maxVelocity
 *   declared max |qd_j| per joint, rad/s
 * @param maxAcceleration
 *   declared max |qdd_j| per joint, rad/s^2
 * @param fracBitLimits
 *   per-node caps below the kinds' fraction bits (chosen by [[ArmConfig.fitted]])
 */
final case class ArmParams(
    chain: SerialChain,
    maxVelocity: Seq[Double],
    maxAcceleration: Seq[Double],
    cordic: CordicParams = CordicParams.tableResidual,
    velocityFracBits: Int = 20,
    accelerationFracBits: Int = 20,
    constantFracBits: Int = 24,
    internalFracBits: Int = 22,
    outputFracBits: Int = 20,
    productRounding: Rounding = Rounding.Truncate,
    multiplierLatency: Int = 1,
    memoryDelayMinCycles: Int = 4,
    scheduleRequest: ScheduleRequest = ScheduleRequest(),
    dynamics: Dynamics = Dynamics.Rnea,
    fracBitLimits: FracBitLimits = FracBitLimits.none
) {

  require(
    maxVelocity.size == chain.size,
    s"robot ${chain.name} has ${chain.size} joints but max-velocity gives ${maxVelocity.size} value(s)"
  )
  require(
    maxAcceleration.size == chain.size,
    s"robot ${chain.name} has ${chain.size} joints but max-acceleration gives ${maxAcceleration.size} value(s)"
  )
  require(
    multiplierLatency >= 1 && multiplierLatency <= 4,
    s"datapath.multiplier-latency must be in 1..4, got $multiplierLatency"
  )
  require(
    memoryDelayMinCycles == 0 || memoryDelayMinCycles >= 2,
    s"datapath.memory-delay-min-cycles must be 0 (registers only) or >= 2, got $memoryDelayMinCycles"
  )

  def jointNames: IndexedSeq[String] = chain.joints.map(_.name)

  val numerics: Numerics = Numerics(
    maxVelocity,
    maxAcceleration,
    cordic,
    velocityFracBits,
    accelerationFracBits,
    constantFracBits,
    internalFracBits,
    outputFracBits,
    productRounding
  )

  /**
   * The dynamics on graph nodes, the datapath's structure written once, and the vector-level bounds proved
   * while building it.
   */
  private lazy val built: (Graph, RangeHints) = dynamics match {
    case Dynamics.Rnea             => ArmParams.rneaGraph(chain, maxVelocity, maxAcceleration)
    case Dynamics.Joint3(model, r) => (ArmParams.joint3Graph(chain, model, r), RangeHints.none)
  }
  lazy val graph: Graph = built._1
  lazy val rangeHints: RangeHints = built._2
  lazy val analysis: Analysis = new Analysis(graph, numerics, rangeHints, fracBitLimits)
  private def scheduleFor(request: ScheduleRequest) =
    new Schedule(analysis, request, cordic, multiplierLatency, ArmDatapath.inputCycle)

  /**
   * The schedule and, with `schedule.storage = memory`, its banks. With memory and `clocks-per-sample
   * \= auto`, the interval is the fewest from the multiplier budget's on at which the banks' read ports can
   * also be served (a tight interval can leave no free port for a value read by many operations).
   */
  private lazy val scheduled: (Schedule, Option[BankedSchedule]) = scheduleRequest.storage match {
    case Storage.Registers => (scheduleFor(scheduleRequest), None)
    case Storage.Memory =>
      val first = scheduleFor(scheduleRequest)
      if (scheduleRequest.clocksPerSample.isDefined) (first, Some(new BankedSchedule(first)))
      else {
        val tries =
          Iterator.range(first.clocksPerSample, first.clocksPerSample + ArmParams.autoIntervalTries).map {
            ii =>
              scala.util.Try {
                val s = scheduleFor(scheduleRequest.copy(clocksPerSample = Some(ii)));
                (s, Some(new BankedSchedule(s)))
              }
          }
        tries
          .collectFirst { case scala.util.Success(found) => found }
          .getOrElse((first, Some(new BankedSchedule(first))))
      }
  }
  lazy val schedule: Schedule = scheduled._1

  /**
   * With `schedule.storage = memory`: the banks, adder units and table of the shared datapath (see
   * [[BankedSchedule]]).
   */
  lazy val banked: Option[BankedSchedule] = scheduled._2

  /** Cycles from a sample on the input port to its torques on the output port. */
  def latency: Int = banked.fold(schedule.latency)(_.latency)

  /** Cycle at which every torque is in its register, before the output stage. */
  def outputsReady: Int = banked.fold(schedule.outputsReady)(_.outputsReady)

  /** Registers of the output stage: memory storage has one more ([[BankedSchedule.outputStages]]). */
  def outputStages: Int = banked.fold(Schedule.outputStages)(_ => BankedSchedule.outputStages)

  /**
   * Worst-case |torque - exact double RNEA at the unquantized inputs| per joint, N·m, for inputs in range.
   */
  def errorBounds: IndexedSeq[Double] = analysis.outputs.map(_.errorBound)
  def errorBound: Double = errorBounds.max

  /**
   * Names the design: robot and joints (or the closed form) and, when samples are spaced, the clocks per
   * sample.
   */
  def tag: String = (dynamics match {
    case Dynamics.Rnea => s"${chain.name.replaceAll("[^A-Za-z0-9]", "_")}_${chain.size}dof"
    case d             => d.name
  }) + (if (schedule.clocksPerSample > 1) s"_ii${schedule.clocksPerSample}" else "") + (if (banked.isDefined)
                                                                                          "_mem"
                                                                                        else "")

  /**
   * The top module's name: `LoadDatapath_<model>` for the joint-3 closed forms (the name their users know),
   * else `ArmDatapath_<tag>`.
   */
  def moduleName: String = dynamics match {
    case Dynamics.Rnea => s"ArmDatapath_$tag"
    case _             => s"LoadDatapath_$tag"
  }
}

object ArmParams {

  /**
   * Intervals tried above the budget's for `clocks-per-sample = auto` with memory storage, before the refusal
   * of the first.
   */
  val autoIntervalTries: Int = 64

  /**
   * Every joint's torque as a graph output, named after the joint; beside it, magnitude bounds that RNEA's
   * vectors prove over the declared ranges (rotations keep lengths), for the range analysis.
   */
  def rneaGraph(
      chain: SerialChain,
      maxVelocity: Seq[Double],
      maxAcceleration: Seq[Double]
  ): (Graph, RangeHints) =
    GraphBuilder.buildWithBounds { b =>
      val va = new TrackingAlgebra(b)
      val state = chain.joints.indices.map { j =>
        JointState(
          va.leaf(b.trig(TrigFn.Cos, AngleSum.of(j)), 1.0),
          va.leaf(b.trig(TrigFn.Sin, AngleSum.of(j)), 1.0),
          va.leaf(b.input(Signal.Velocity(j)), maxVelocity(j)),
          va.leaf(b.input(Signal.Acceleration(j)), maxAcceleration(j))
        )
      }
      val torques = Rnea.torques(chain, state)(va)
      (chain.joints.map(_.name).zip(torques.map(_.node)), va.hints)
    }

  /** The joint-3 closed form of planar3 as a graph of one output, named after the chain's third joint. */
  def joint3Graph(chain: SerialChain, model: LoadModel, robot: RobotParams): Graph = {
    require(
      chain.size == 3,
      s"the joint-3 closed form needs a 3-joint chain, ${chain.name} has ${chain.size}"
    )
    GraphBuilder.build { b =>
      Seq(
        chain.joints(2).name -> Joint3Load.torque(
          robot,
          model,
          (fn, angle) => b.trig(fn, angle),
          j => b.input(Signal.Velocity(j)),
          j => b.input(Signal.Acceleration(j))
        )(b)
      )
    }
  }
}

/** The arm a configuration describes: its chain and per-joint ranges resolved against it. */
object ArmConfig {
  import reducerload.load.LoadParams
  import reducerload.robot.{Planar3, Urdf}

  /** The serial chain of `p.robot`: the built-in planar arm, or the URDF file's chain to its tip. */
  def chain(p: LoadParams): SerialChain =
    if (p.robot.isPlanar3) Planar3.chain(p.robot)
    else Urdf.read(java.nio.file.Paths.get(p.robot.source), Option(p.robot.tip).filter(_.nonEmpty))

  /** One value for every joint, one per joint, or (velocities only) none: the URDF's limits. */
  private def perJoint(
      chain: SerialChain,
      values: Seq[Double],
      key: String,
      fromUrdf: Option[IndexedSeq[Option[Double]]]
  ): Seq[Double] =
    values.size match {
      case 0 =>
        val limits =
          fromUrdf.getOrElse(throw new IllegalArgumentException(s"$key must be declared for ${chain.name}"))
        chain.joints.zip(limits).map { case (j, l) =>
          l.getOrElse(
            throw new IllegalArgumentException(
              s"joint ${j.name} has no <limit velocity> in the URDF: declare $key"
            )
          )
        }
      case 1                    => Seq.fill(chain.size)(values.head)
      case n if n == chain.size => values
      case n =>
        throw new IllegalArgumentException(
          s"robot ${chain.name} has ${chain.size} joints but $key gives $n values"
        )
    }

  /**
   * The datapath's parameters from a configuration (fraction bits fitted to `numeric.target-error` if set).
   */
  def apply(p: LoadParams): ArmParams = {
    val asSet = configured(p)
    if (p.targetError.isEmpty) asSet else fitted(asSet, perOutput(asSet, p.targetError))
  }

  /** A target per torque the datapath computes: one value for all, or one each. */
  private def perOutput(p: ArmParams, targets: Seq[Double]): Seq[Double] = {
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
    (q, d) => q.copy(outputFracBits = q.outputFracBits + d),
    (q, d) => q.copy(constantFracBits = q.constantFracBits + d),
    (q, d) => q.copy(velocityFracBits = q.velocityFracBits + d),
    (q, d) => q.copy(accelerationFracBits = q.accelerationFracBits + d),
    (q, d) => q.copy(internalFracBits = q.internalFracBits + d)
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
      .Try(
        p.copy(
          velocityFracBits = p.velocityFracBits + d,
          accelerationFracBits = p.accelerationFracBits + d,
          constantFracBits = p.constantFracBits + d,
          internalFracBits = p.internalFracBits + d,
          outputFracBits = p.outputFracBits + d
        )
      )
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

  private def configured(p: LoadParams): ArmParams = {
    val c = chain(p)
    ArmParams(
      c,
      perJoint(c, p.robot.maxVelocity, "robot.max-velocity", Some(c.joints.map(_.velocityLimit))),
      perJoint(c, p.robot.maxAcceleration, "robot.max-acceleration", None),
      cordic = p.cordic,
      velocityFracBits = p.velocityFracBits,
      accelerationFracBits = p.accelerationFracBits,
      constantFracBits = p.constantFracBits,
      internalFracBits = p.internalFracBits,
      outputFracBits = p.outputFracBits,
      productRounding = p.productRounding,
      multiplierLatency = p.multiplierLatency,
      memoryDelayMinCycles = p.memoryDelayMinCycles,
      scheduleRequest = p.schedule,
      dynamics = if (p.model.closedForm) Dynamics.Joint3(p.model, p.robot) else Dynamics.Rnea
    )
  }
}
