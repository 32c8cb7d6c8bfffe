package reducerload.arm

import reducerload.config.DatapathParams
import reducerload.cordic.CordicParams
import reducerload.dynamics.{CosSin, JointState, Rnea, Sym3, V3}
import reducerload.fixedpoint.Rounding
import reducerload.graph._
import reducerload.load.{Joint3Load, LoadModel}
import reducerload.pipeline.PipelinedMultiplier
import reducerload.robot.{RobotParams, SerialChain}

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
 * @param cordic
 *   the sin/cos unit as configured: its numerics; the unit built, with its timing, is `schedule.cordic`
 * @param datapath
 *   the configuration's `datapath.*` settings (fraction bits moved by the target-error fit)
 * @param fracBitLimits
 *   per-node caps below the kinds' fraction bits (chosen by [[reducerload.compiler.TargetFit]])
 * @param payload
 *   a payload on the last joint whose inertial parameters are run-time inputs (None: no payload, no inputs)
 * @param gravity
 *   the gravity vector as three run-time inputs (None: the chain's gravity, folded at elaboration)
 */
final case class ArmParams(
    chain: SerialChain,
    maxVelocity: Seq[Double],
    maxAcceleration: Seq[Double],
    cordic: CordicParams = CordicParams.tableResidual,
    datapath: DatapathParams = DatapathParams(),
    scheduleRequest: ScheduleRequest = ScheduleRequest(),
    dynamics: Dynamics = Dynamics.Rnea,
    fracBitLimits: FracBitLimits = FracBitLimits.none,
    payload: Option[PayloadSpec] = None,
    gravity: Option[GravitySpec] = None
) {
  require(
    payload.isEmpty || dynamics == Dynamics.Rnea,
    s"payload.enabled = true needs model rnea (the ${dynamics.name} closed form has no payload)"
  )
  require(
    gravity.isEmpty || dynamics == Dynamics.Rnea,
    s"gravity.runtime = true needs model rnea (the ${dynamics.name} closed form has its gravity folded)"
  )
  gravity.foreach(g =>
    require(
      chain.gravity.norm <= g.maxMagnitude,
      s"gravity.max-magnitude (${g.maxMagnitude} m/s^2) is below the robot's own gravity (${chain.gravity.norm} m/s^2), the reset value"
    )
  )

  require(
    maxVelocity.size == chain.size,
    s"robot ${chain.name} has ${chain.size} joints but max-velocity gives ${maxVelocity.size} value(s)"
  )
  require(
    maxAcceleration.size == chain.size,
    s"robot ${chain.name} has ${chain.size} joints but max-acceleration gives ${maxAcceleration.size} value(s)"
  )
  def velocityFracBits: Int = datapath.velocityFracBits
  def accelerationFracBits: Int = datapath.accelerationFracBits
  def constantFracBits: Int = datapath.constantFracBits
  def internalFracBits: Int = datapath.internalFracBits
  def outputFracBits: Int = datapath.outputFracBits
  def productRounding: Rounding = datapath.productRounding
  def multiplierLatency: Int = datapath.multiplierLatency
  def memoryDelayMinCycles: Int = datapath.memoryDelayMinCycles

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
    productRounding,
    payload.fold(Map.empty[Signal.Parameter, Interval])(_.ranges(chain)) ++
      gravity.fold(Map.empty[Signal.Parameter, Interval])(_.ranges)
  )

  /**
   * The runs of parallel axes RNEA crosses in one rotation (`datapath.compose-parallel-axes`, model rnea).
   */
  lazy val composedRuns: Seq[Range] =
    if (dynamics == Dynamics.Rnea && datapath.composeParallelAxes) Rnea.parallelRuns(chain).filter(_.size > 1)
    else Nil

  /**
   * The dynamics on graph nodes, the datapath's structure written once, and the vector-level bounds proved
   * while building it.
   */
  private lazy val built: (Graph, RangeHints) = {
    val (written, hints) = dynamics match {
      case Dynamics.Rnea =>
        ArmParams.rneaGraph(
          chain,
          maxVelocity,
          maxAcceleration,
          payload,
          gravity,
          datapath.composeParallelAxes
        )
      case Dynamics.Joint3(model, r) => (ArmParams.joint3Graph(chain, model, r), RangeHints.none)
    }
    datapath.reassociate match {
      case Reassociation.Off  => (written, hints)
      case Reassociation.Sums => Reassociate(written, hints, arrivalDelays)
      case Reassociation.SumsAndProducts =>
        val (g, h) = Reassociate(written, hints, arrivalDelays, products = true)
        Reassociate.distributeConstants(g, h, arrivalDelays)
    }
  }

  /**
   * Clocks of an addition, a product (of two operands of two 17-bit chunks, the arms' usual shape) and a
   * sin/cos in the one-sample-per-clock datapath: the weights that order a sum's terms for
   * `datapath.reassociate`, the same for every schedule of the design (the fraction-bit caps are fitted on
   * its graph).
   */
  def arrivalDelays: ArrivalDelays = ArrivalDelays(
    add = 1,
    mul = PipelinedMultiplier.latency(35, 35) + multiplierLatency,
    trig = 1 + cordic.latency
  )
  lazy val graph: Graph = built._1
  lazy val rangeHints: RangeHints = built._2
  lazy val analysis: Analysis = new Analysis(graph, numerics, rangeHints, fracBitLimits)
  private def scheduleFor(request: ScheduleRequest) =
    new Schedule(
      analysis,
      request,
      cordic,
      multiplierLatency,
      ArmDatapath.inputCycle,
      memoryDelayMinCycles,
      datapath.registeredRoutes
    )

  /**
   * The schedule and, with memory storage, its banks. With memory storage and an automatic interval, the
   * interval is the fewest from the multiplier budget's on at which the banks' read ports can also be served
   * (a tight interval can leave no free port for a value read by many operations).
   */
  private lazy val scheduled: (Schedule, Option[BankedSchedule]) = scheduleRequest.stored match {
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

  /**
   * How each value reaches its reads in a shared registers datapath ([[HeldTaps]]; None: a constant, a
   * product forwarded to its one reader, a product or a sum below the root of an accumulated tree, a product
   * read from its unit's [[reducerload.graph.ProductMemory]], a sin or cos read only from
   * [[reducerload.graph.SinCosMemory]]s, or a design with one clock per sample or memory storage).
   */
  def heldTaps(id: NodeId): Option[HeldTaps] =
    if (
      schedule.dedicated || banked.isDefined || schedule.forwarded(id) ||
      schedule.accumulation(id).exists(_.root != id) || schedule.productMemoryOf.contains(id)
    ) None
    else
      (schedule(id), schedule.ownReads(id)) match {
        case (Some(ready), reads) if reads.nonEmpty =>
          Some(HeldTaps(schedule.clocksPerSample, ready, reads, memoryDelayMinCycles))
        case _ => None
      }

  /**
   * Register bits holding values between their cycles in a shared registers datapath: each value's first
   * register and its chain, the stretches in block RAM left out ([[HeldTaps]]), and the registers products
   * take turns in ([[reducerload.graph.SharedRegister]]) once each, the readers' copies
   * ([[reducerload.graph.Schedule.readerCopies]]), the accumulators of accumulated trees (each as wide as its
   * root) and the registers in logic after each [[reducerload.graph.ProductMemory]] and
   * [[reducerload.graph.SinCosMemory]].
   */
  def heldRegisterBits: Long =
    unsharedTaps.map { case (id, taps) => taps.registerBits(analysis(id).format.width) }.sum +
      schedule.sharedRegisters.map(_.width.toLong).sum +
      schedule.accumulations.map(a => analysis(a.root).format.width.toLong).sum +
      schedule.readerCopies.map { case (id, units) => units.size.toLong * analysis(id).format.width }.sum +
      schedule.productMemories.map(_.width.toLong * ProductMemory.fabricRegisters).sum +
      schedule.sinCosMemories.map(m => sinCosWidth(m).toLong * ProductMemory.fabricRegisters).sum

  /**
   * Registers holding values in a shared registers datapath (each of a chain, a shared one once, a reader's
   * copy, an accumulator, a product memory's registers in logic).
   */
  def heldRegisters: Int =
    unsharedTaps.map(_._2.registers).sum + schedule.sharedRegisters.size + schedule.readerCopyCount +
      schedule.accumulations.size +
      (schedule.productMemories.size + schedule.sinCosMemories.size) * ProductMemory.fabricRegisters

  /** Bits of a [[reducerload.graph.SinCosMemory]]'s word: its values'. */
  def sinCosWidth(m: reducerload.graph.SinCosMemory): Int = analysis(m.reads.head.value).format.width

  /** The held values with registers of their own, and their taps. */
  private def unsharedTaps: Seq[(NodeId, HeldTaps)] =
    graph.ids.filterNot(schedule.sharedRegisterOf.contains).flatMap(id => heldTaps(id).map(id -> _))

  /** Cycles from a sample on the input port to its torques on the output port. */
  def latency: Int = banked.fold(schedule.latency)(_.latency)

  /** Cycle at which every torque is in its register, before the output stage. */
  def outputsReady: Int = banked.fold(schedule.outputsReady)(_.outputsReady)

  /**
   * Registers of the output stage: memory storage and registered routes have one more
   * ([[Schedule.outputStages]]).
   */
  def outputStages: Int = banked.fold(schedule.outputStages)(_ => BankedSchedule.outputStages)

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
  }) + (if (payload.isDefined) "_payload" else "") +
    (if (gravity.isDefined) "_gravity" else "") + (if (schedule.clocksPerSample > 1)
                                                     s"_ii${schedule.clocksPerSample}"
                                                   else "") + (if (banked.isDefined)
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
   * vectors prove over the declared ranges (rotations keep lengths), for the range analysis. With
   * `composeParallelAxes` each run of parallel axes is crossed in one rotation by its summed angle
   * ([[Rnea.torques]]).
   */
  def rneaGraph(
      chain: SerialChain,
      maxVelocity: Seq[Double],
      maxAcceleration: Seq[Double],
      payload: Option[PayloadSpec] = None,
      gravity: Option[GravitySpec] = None,
      composeParallelAxes: Boolean = false
  ): (Graph, RangeHints) =
    GraphBuilder.buildWithBounds { b =>
      val va = new TrackingAlgebra(b)
      // cos and sin of an angle sum: one CORDIC angle (binary angles add).
      def cosSin(angle: AngleSum) =
        CosSin(va.leaf(b.trig(TrigFn.Cos, angle), 1.0), va.leaf(b.trig(TrigFn.Sin, angle), 1.0))
      val state = chain.joints.indices.map { j =>
        val cs = cosSin(AngleSum.of(j))
        JointState(
          cs.cos,
          cs.sin,
          va.leaf(b.input(Signal.Velocity(j)), maxVelocity(j)),
          va.leaf(b.input(Signal.Acceleration(j)), maxAcceleration(j))
        )
      }
      // The payload's ten parameters as inputs, each with its declared bound; its body at the last joint's
      // origin is computed from them per sample.
      val added = payload.map { spec =>
        val ranges = spec.ranges(chain)
        def in(p: InertialParameter) = {
          val s = Signal.Inertial(spec.joint(chain), p)
          va.leaf(b.input(s), ranges(s).maxAbs)
        }
        spec.joint(chain) -> spec.added(
          in(InertialParameter.Mass),
          V3(in(InertialParameter.Com(0)), in(InertialParameter.Com(1)), in(InertialParameter.Com(2))),
          Sym3.tabulate((r, c) => in(InertialParameter.Inertia(r, c)))
        )(va)
      }
      // The run-time gravity's three components as inputs, each within the declared magnitude.
      val runtimeGravity = gravity.map { spec =>
        val g = Signal.gravity.map(s => va.leaf(b.input(s), spec.maxMagnitude))
        V3(g(0), g(1), g(2))
      }
      val summed = Option.when(composeParallelAxes)((span: Range) => cosSin(AngleSum.of(span: _*)))
      val torques = Rnea.torques(chain, state, added.toMap, runtimeGravity, summed)(va)
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
