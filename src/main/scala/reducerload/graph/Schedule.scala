package reducerload.graph

import reducerload.util.IntMath.ceilDiv

import reducerload.cordic.CordicParams
import reducerload.fixedpoint.Rounding
import reducerload.pipeline.{PipelinedMultiplier, ShiftAddMultiplier}

/** How a multiply by a folded robot constant is built (`schedule.constant-multiplies`). */
sealed abstract class ConstantMultiplies(val name: String) { override def toString: String = name }
object ConstantMultiplies {

  /** On the 18x18 multiplier units, shared like every other multiply. */
  case object Blocks extends ConstantMultiplies("blocks")

  /** Each its own adder tree of the constant's signed digits, in logic elements ([[ShiftAddMultiplier]]). */
  case object ShiftAdd extends ConstantMultiplies("shift-add")
  val all: Seq[ConstantMultiplies] = Seq(Blocks, ShiftAdd)
}

/** Which algorithm places a registers-storage schedule's operations in time (`schedule.scheduler`). */
sealed abstract class Scheduler(val name: String) { override def toString: String = name }
object Scheduler {

  /** The list schedule, then the shortest the solver finds from it ([[LatencySearch]]). */
  case object CpSat extends Scheduler("cp-sat")

  /** The list schedule alone (its order: `schedule.list-order`). */
  case object ListOnly extends Scheduler("list")
  val all: Seq[Scheduler] = Seq(CpSat, ListOnly)
}

/**
 * What a user asks of the schedule; `None` means derive it.
 *
 * @param clocksPerSample
 *   the initiation interval: a new sample may enter every this many clocks (None: `auto`, chosen by the
 *   compiler's device fit; a schedule built from it without the fit takes the fewest the budget allows)
 * @param maxMultipliers
 *   18x18 multiplier blocks the datapath may use (None: no budget)
 * @param cordicUnits
 *   sin/cos units (None: the fewest that do not lengthen the interval)
 * @param storage
 *   where values wait between operations ([[Storage]]; None: `auto`, chosen by the device fit, registers
 *   without it)
 * @param constantMultiplies
 *   how a multiply by a robot constant is built ([[ConstantMultiplies]])
 * @param listOrder
 *   the memory-storage list scheduler's order ([[ListOrder]]; None: `auto`, the one with the least latency);
 *   with registers only `by-height` (None: the graph's order)
 * @param adderUnits
 *   memory storage's shared adder units (None: the fewest that take every addition)
 * @param listTries
 *   memory storage: by-height schedules tried, the first in the plain order, the others with perturbed
 *   priorities
 * @param refinement
 *   registers storage at 2 clocks per sample or more: annealing steps per operation refining the list
 *   schedule ([[RefinementProblem]]; 0: the list schedule as it is)
 * @param scheduler
 *   registers storage at 2 clocks per sample or more: the list schedule alone, or the shortest the solver
 *   finds from it ([[Scheduler]])
 * @param shareRegisters
 *   registers storage at 2 clocks per sample or more: products of one unit whose cycles from ready to last
 *   read do not meet modulo the interval take turns in one register ([[SharedRegister]]) instead of a
 *   register each
 * @param readerCopies
 *   registered routes: a value read within its first interval by several multiplier units, a clock or more
 *   after it is ready, reaches all but one of them through a copy of its register ([[Schedule.readerCopies]])
 * @param forwardSlack
 *   registered routes (`datapath.registered-routes`): a product read by one addition only is taken off its
 *   unit's output a cycle early, with no register of its own, when its slack on the dependences is at most
 *   this many clocks (0: on a longest path); None: none (direct routes forward every such product)
 * @param accumulateSlack
 *   registers storage at 2 clocks per sample or more: a tree of additions of products read once
 *   ([[Accumulation]]) is summed by an accumulator that takes each product off its unit in turn, when the
 *   clocks that costs over a tree of adders ([[Accumulation.latencyCost]]) are within the dependences' slack
 *   of its root plus this many; None: none
 * @param productMemories
 *   registers storage at 2 clocks per sample or more: each multiplier unit writes its product into a block
 *   RAM every clock, and truncated products read [[ProductMemory.readDelay]] clocks or more after they are
 *   ready, within the interval, are read from it instead of a register of their own, one read per cycle
 *   ([[ProductMemory]]); the refinement moves reads into those windows, apart on the read ports
 * @param sinCosMemories
 *   registers storage at 2 clocks per sample or more: each CORDIC unit writes its sine and its cosine into
 *   block RAMs every clock, and sin/cos reads [[ProductMemory.readDelay]] clocks or more after they are ready
 *   are read from them instead of the value's registers, one read per cycle and memory ([[SinCosMemory]])
 */
final case class ScheduleRequest(
    clocksPerSample: Option[Int] = None,
    maxMultipliers: Option[Int] = None,
    cordicUnits: Option[Int] = None,
    storage: Option[Storage] = None,
    constantMultiplies: ConstantMultiplies = ConstantMultiplies.Blocks,
    listOrder: Option[ListOrder] = None,
    adderUnits: Option[Int] = None,
    listTries: Int = ScheduleRequest.defaultListTries,
    refinement: Int = ScheduleRequest.defaultRefinement,
    scheduler: Scheduler = Scheduler.ListOnly,
    shareRegisters: Boolean = false,
    readerCopies: Boolean = false,
    forwardSlack: Option[Int] = None,
    accumulateSlack: Option[Int] = None,
    productMemories: Boolean = false,
    sinCosMemories: Boolean = false
) {
  require(
    listOrder.isEmpty || stored == Storage.Memory || listOrder.contains(ListOrder.ByHeight),
    s"schedule.list-order = ${listOrder.get} orders the block-RAM schedule: it needs " +
      s"schedule.storage = memory (or list-order auto or by-height)"
  )
  require(
    adderUnits.isEmpty || stored == Storage.Memory,
    s"schedule.adder-units = ${adderUnits.get} shares adders between additions: it needs schedule.storage " +
      s"= memory (or adder-units auto)"
  )
  require(
    adderUnits.forall(a => a >= 1 && a <= 4096),
    s"schedule.adder-units must be auto or in 1..4096, got ${adderUnits.get}"
  )

  /** The storage the schedule is built for: as asked, registers while `auto` is not resolved by a fit. */
  def stored: Storage = storage.getOrElse(Storage.Registers)

  require(listTries >= 1 && listTries <= 1024, s"schedule.list-tries must be in 1..1024, got $listTries")
  require(
    forwardSlack.forall(s => s >= 0 && s <= 4096),
    s"schedule.forward-slack must be none or in 0..4096 clocks, got ${forwardSlack.get}"
  )
  require(
    accumulateSlack.forall(s => s >= 0 && s <= 4096),
    s"schedule.accumulate-slack must be none or in 0..4096 clocks, got ${accumulateSlack.get}"
  )
  require(
    refinement >= 0 && refinement <= 1000000,
    s"schedule.refinement must be in 0..1000000 steps per operation, got $refinement"
  )
  require(
    constantMultiplies == ConstantMultiplies.Blocks || stored == Storage.Registers,
    "schedule.constant-multiplies = shift-add needs schedule.storage = registers " +
      "(block-RAM banks feed shared units only)"
  )
  require(
    clocksPerSample.forall(c => c >= 1 && c <= 4096),
    s"schedule.clocks-per-sample must be auto or in 1..4096, got ${clocksPerSample.get}"
  )
  require(
    maxMultipliers.forall(m => m >= 1 && m <= 100000),
    s"schedule.max-multipliers must be none or in 1..100000, got ${maxMultipliers.get}"
  )
  require(
    cordicUnits.forall(c => c >= 1 && c <= 4096),
    s"schedule.cordic-units must be auto or in 1..4096, got ${cordicUnits.get}"
  )
}

object ScheduleRequest {

  /**
   * By-height schedules tried by default: on the larger arms the best of the perturbed tries has a few
   * percent less latency than the plain order, and a try costs tens of milliseconds.
   */
  val defaultListTries: Int = 32

  /**
   * Refinement steps per operation by default: on the UR5 at 17 clocks per sample (1e-3 N·m) 20,000 (8.4 M
   * steps, about 2 s) take the operand-multiplexer input bits from 10,176 to 7,208, the held register bits
   * from 8,586 to 7,060 and the block-RAM delays from 74 to 57 at the list schedule's latency; 100,000 (five
   * times the time) save about 400 LEs more (docs/benchmarks.md, SchedulerComparison).
   */
  val defaultRefinement: Int = 20000
}

/**
 * Operand widths of a multiplier unit, wider operand first: its 18x18 blocks and its pipeline depth follow.
 */
final case class MulShape(wide: Int, narrow: Int) {
  def blocks: Int = PipelinedMultiplier.blocks(wide, narrow)
  def max(o: MulShape): MulShape = MulShape(math.max(wide, o.wide), math.max(narrow, o.narrow))

  /** Bits of a full product of the two ports. */
  def productBits: Int = wide + narrow

  /** Each port's width, in the order of [[Schedule.ports]]: wide, narrow. */
  def widths: IndexedSeq[Int] = IndexedSeq(wide, narrow)
  override def toString: String = s"${wide}x$narrow"
}
object MulShape {
  def of(a: Int, b: Int): MulShape = MulShape(math.max(a, b), math.min(a, b))

  /** 17-bit chunks of each operand ([[PipelinedMultiplier]]): what a product costs in blocks and clocks. */
  def chunks(s: MulShape): (Int, Int) =
    (PipelinedMultiplier.chunkCount(s.wide), PipelinedMultiplier.chunkCount(s.narrow))
}

/** Multiplies that need the same 18x18 blocks, and the shape of a unit that takes any of them. */
final case class MulClass(shape: MulShape, ops: IndexedSeq[NodeId])

/**
 * Where and when an operation runs: its unit (multiplies and sin/cos only) and the cycle it reads its
 * operands.
 */
final case class Slot(unit: Option[Int], issue: Int)

/**
 * The list scheduler's state after each node: ready cycles, issues, occupied (is multiplier, unit, residue),
 * angles placed.
 */
private final case class ScheduleState(
    ready: Vector[Option[Int]],
    slots: Vector[Option[Slot]],
    taken: Set[(Boolean, Int, Int)],
    angleSlots: Map[AngleSum, Slot],
    forwarded: Set[NodeId],
    chains: Set[Accumulation] = Set.empty
)

/**
 * Modulo schedule of a graph: a sample enters every `clocksPerSample` clocks (the initiation interval II) and
 * the samples in flight share multiplier units and CORDIC units, each unit taking at most one operation per
 * residue of the cycle modulo II; additions, subtractions and negations are each their own adder (an adder
 * costs about what a shared adder's operand multiplexers would). Cycles are counted from the clock a sample
 * is taken on the input port (cycle 0). The bit-accurate model does not depend on any of this: the numerics
 * stay on the graph's nodes.
 *
 * List scheduling in the graph's order (RNEA's own order, which keeps few values alive): each operation at
 * its operands' ready cycle or, for a multiply, at the first later cycle whose residue has a free unit. The
 * graph has no recurrence, so every II at or above the resource bound is met. `clocksPerSample = 1` with no
 * budget gives every operation its own operator: the ASAP schedule. With `schedule.scheduler = cp-sat` a
 * solver then looks for a shorter schedule of the same units from it ([[LatencySearch]], registers storage).
 *
 * Timing of one operation issued (reading its operands) in cycle r:
 *   - add/sub/neg: result registered, ready at r + 1;
 *   - multiply: the unit's pipelined multiplier ([[PipelinedMultiplier.latency]] plus `multiplierLatency - 1`
 *     registers) then, when units are shared or the product rounds, a register that captures it: ready at r +
 *     multiplier latency (+ 1), and [[Schedule.routeStages]] more on a unit with registered routes;
 *   - multiply by a constant as shift-and-add logic (`shiftAdded`): its own registered adder tree, one level
 *     per clock ([[ShiftAddMultiplier.latency]]), then the capture register as above;
 *   - sin/cos of an angle sum: the sum registered, then the CORDIC unit, then (shared) a capture register;
 *   - a tree of additions of products accumulated (`schedule.accumulate-slack`, [[Accumulation]]): its
 *     products leave their units in residues of their own within an interval, each into its unit's register
 *     of rounded products in the cycle before its own register would hold it, through the accumulator's term
 *     register into its adder; the root's register is written with the last, so it is ready
 *     [[Accumulation.rootDelay]] after the last product would be, and the products and the sums below the
 *     root have none.
 * Every value is held in a chain of registers written once per sample (see `stages`).
 *
 * @param requestedCordic
 *   the CORDIC unit as configured; `cordic` is the one built (with its table's route register where routes
 *   are registered)
 * @param inputCycle
 *   cycle at which the clamped velocities and accelerations are in registers (the angles are in the input
 *   register from cycle 1)
 * @param memoryDelayMinCycles
 *   `datapath.memory-delay-min-cycles`: values held that long or longer wait in block RAM ([[HeldTaps]]),
 *   which the refinement counts
 * @param registeredRoutes
 *   `datapath.registered-routes`: with shared units, [[Schedule.routeStages]] more clocks per multiply on a
 *   unit, no product forwarded (but those `schedule.forward-slack` names), and a three-register output stage
 *   (see `routed`); None (`auto`): above [[Schedule.directMaxClocks]] clocks per sample
 */
final class Schedule(
    val analysis: Analysis,
    val request: ScheduleRequest,
    requestedCordic: CordicParams,
    multiplierLatency: Int,
    val inputCycle: Int,
    memoryDelayMinCycles: Int = 0,
    registeredRoutes: Option[Boolean] = Some(false)
) {
  import Op._
  private val graph = analysis.graph
  private val ids = graph.ids
  private def isConst(x: NodeId) = graph(x).isInstanceOf[Const]

  /**
   * Multiplies by a constant built as shift-and-add logic (`schedule.constant-multiplies = shift-add`): no
   * unit, no block.
   */
  val shiftAdded: Set[NodeId] =
    if (request.constantMultiplies != ConstantMultiplies.ShiftAdd) Set.empty
    else
      ids.filter(id => graph(id) match { case Mul(a, b) => isConst(a) || isConst(b); case _ => false }).toSet

  /** The variable operand and the constant's code of a shift-add multiply. */
  def shiftAddOperands(id: NodeId): (NodeId, BigInt) = {
    val Mul(a, b) = graph(id): @unchecked
    val (c, x) = if (isConst(a)) (a, b) else (b, a)
    (x, analysis(c).raw.get)
  }

  /** Multiplies on the multiplier units. */
  private val muls: IndexedSeq[NodeId] = ids.filter(id => graph(id).isInstanceOf[Mul] && !shiftAdded(id))
  private val angles = graph.angles.toIndexedSeq

  /** Operand shape of a multiply. */
  def shapeOf(id: NodeId): MulShape = {
    val Mul(a, b) = graph(id): @unchecked
    MulShape.of(analysis(a).format.width, analysis(b).format.width)
  }

  /**
   * Multiplies grouped by the 18x18 blocks their operands need (17-bit chunks per operand): a shared unit of
   * a class is as wide as its widest multiply, so a few wide products do not make every unit wide. Narrowest
   * class first.
   */
  val classes: IndexedSeq[MulClass] = muls
    .groupBy(id => MulShape.chunks(shapeOf(id)))
    .toIndexedSeq
    .sortBy(_._1)
    .map { case (_, ops) => MulClass(ops.map(shapeOf).reduce(_ max _), ops) }

  /** Shortest interval the CORDIC units allow. */
  private def cordicBound(units: Int): Int = if (angles.isEmpty) 1 else ceilDiv(angles.size, units)

  /**
   * CORDIC units at interval `ii`: asked, or the fewest that keep it; none for a robot whose torques need no
   * sin/cos (a joint turning about the gravity axis with massless links after it), so no unit is built with
   * nothing to do.
   */
  private def cordicUnitsAt(ii: Int): Int =
    if (angles.isEmpty) 0 else request.cordicUnits.getOrElse(math.max(1, ceilDiv(angles.size, ii)))

  /**
   * Operations a shared unit takes per sample at interval `ii`: every slot with registers; with memory
   * storage an eighth stays free, so that bank read ports and unit slots can still meet.
   */
  def slotsPerUnit(ii: Int): Int = if (request.stored == Storage.Memory) math.max(1, ii - ii / 8) else ii

  /** Units that take `ops` operations at interval `ii`. */
  def unitsFor(ops: Int, ii: Int): Int = ceilDiv(ops, slotsPerUnit(ii))

  /**
   * 18x18 blocks at interval `ii`: per class, the fewest units that take its multiplies in `slotsPerUnit(ii)`
   * slots each, and the CORDIC units'.
   */
  private def blocksFor(ii: Int): Int =
    classes.map(c => unitsFor(c.ops.size, ii) * c.shape.blocks).sum + cordicUnitsAt(
      ii
    ) * requestedCordic.multiplierBlocks

  /** The fewest blocks any interval needs: one unit per class, the fewest CORDIC units. */
  private val leastBlocks: Int = blocksFor(math.max(1, math.max(muls.size, angles.size)))

  /** Shortest interval within `budget` blocks that the CORDIC units allow. */
  private def fewestClocks(budget: Int): Option[Int] =
    (1 to math.max(1, math.max(muls.size, angles.size))).find(c =>
      blocksFor(c) <= budget && cordicBound(cordicUnitsAt(c)) <= c
    )

  /** The initiation interval: asked, or the fewest clocks the multiplier budget and CORDIC units allow. */
  val clocksPerSample: Int = request.clocksPerSample.getOrElse {
    val byCordic = request.cordicUnits.map(cordicBound).getOrElse(1)
    val byBudget = request.maxMultipliers.map { budget =>
      fewestClocks(budget).getOrElse(
        throw new IllegalArgumentException(
          s"schedule.max-multipliers = $budget is below one multiplier unit per operand width " +
            s"(${classes.map(_.shape).mkString(", ")} bits) " +
            s"and the CORDIC units' products: $leastBlocks blocks; use at least $leastBlocks"
        )
      )
    }
    math.max(byBudget.getOrElse(1), byCordic)
  }
  private val ii = clocksPerSample

  /**
   * Whether each multiply has its own unit (II = 1: no operand multiplexers, no capture register unless it
   * rounds).
   */
  val dedicated: Boolean = ii == 1

  /**
   * `datapath.registered-routes` as decided for this interval (`auto`: above [[Schedule.directMaxClocks]]).
   */
  private def routesRegistered: Boolean = registeredRoutes.getOrElse(ii > Schedule.directMaxClocks)

  /**
   * Routes between value registers and shared units pass registers (`datapath.registered-routes`; the
   * hardware in ArmDatapath): registers storage with shared units only (memory storage's routes pass
   * registers already). The bit-accurate model does not change.
   */
  val routed: Boolean = routesRegistered && !dedicated && request.stored == Storage.Registers

  /**
   * The CORDIC units as built: the route from the start table's block RAM to the first rotation adder gets a
   * register in logic ([[CordicParams.tableRouteRegister]]) wherever routes are registered, in either storage
   * (`registered-routes = true` at any interval; `auto` above [[Schedule.directMaxClocks]] clocks per
   * sample): on a full device that route is as long as the others.
   */
  val cordic: CordicParams =
    requestedCordic.copy(tableRouteRegister = requestedCordic.tableRouteRegister || routesRegistered)

  /**
   * Registers between a sum of several joint angles and its CORDIC unit's input multiplexer: one wherever
   * routes are registered, as for the CORDIC table (the sum's carry chains and the multiplexer in one clock
   * limited the clock: docs/timing-closure.md), none for a joint's own angle.
   */
  def angleSumStages(angle: AngleSum): Int = if (routesRegistered && angle.weight > 1) 1 else 0

  /** The first cycle `angle` can be issued to a CORDIC unit. */
  private def angleEarliest(angle: AngleSum): Int = Schedule.firstAngleCycle + angleSumStages(angle)

  /**
   * Each multiplier unit's shape: one unit per multiply at II = 1, else per class the fewest that fit its
   * multiplies in II slots.
   */
  private val unitShapes: IndexedSeq[MulShape] =
    if (dedicated) classes.flatMap(_.ops.map(shapeOf))
    else classes.flatMap(c => Seq.fill(unitsFor(c.ops.size, ii))(c.shape))
  def multiplierUnits: Int = unitShapes.size

  /** The operand widths unit `u` is built for: its one multiply's at II = 1, its class's widest otherwise. */
  def unitShape(u: Int): MulShape = if (dedicated) shapeOf(mulBindings(u).head._2) else unitShapes(u)

  /** Units per shape, for reports: "15 x 35x31, 1 x 36x31", or one per multiply. */
  def unitSummary: String =
    if (dedicated) s"$multiplierUnits units, one per multiply at its own width"
    else
      unitShapes
        .groupBy(identity)
        .toSeq
        .sortBy(_._1.blocks)
        .map { case (sh, us) => s"${us.size} x $sh" }
        .mkString(", ")

  /**
   * Units of each class, as a range of unit numbers (at II = 1 a multiply's own unit is found by `place`).
   */
  private val classUnits: Map[Int, Range] = {
    val sizes = classes.map(c => if (dedicated) c.ops.size else unitsFor(c.ops.size, ii))
    classes.indices.map(k => k -> (sizes.take(k).sum until sizes.take(k + 1).sum)).toMap
  }
  private val classOf: Map[NodeId, Int] = classes.zipWithIndex.flatMap { case (c, k) =>
    c.ops.map(_ -> k)
  }.toMap

  /** The shared units a multiply may run on: its class's (at II = 1 every unit of the class). */
  def unitsOf(id: NodeId): Range = classUnits(classOf(id))

  /** CORDIC units: asked, or the fewest that keep the interval. */
  val cordicUnits: Int = cordicUnitsAt(ii)

  /** 18x18 blocks of the datapath: its multiplier units' and its CORDIC units' (the whole budget). */
  val multiplierBlocks: Int = unitShapes.map(_.blocks).sum + cordicUnits * cordic.multiplierBlocks

  request.maxMultipliers.foreach { budget =>
    require(
      multiplierBlocks <= budget,
      s"schedule.max-multipliers = $budget is below the $multiplierBlocks blocks that " +
        s"schedule.clocks-per-sample = $ii needs (${muls.size} multiplies on $multiplierUnits " +
        s"units, $cordicUnits CORDIC units); " +
        fewestClocks(budget).fold(s"use max-multipliers >= $multiplierBlocks")(c =>
          s"use clocks-per-sample >= $c or max-multipliers >= $multiplierBlocks"
        )
    )
  }

  require(
    angles.isEmpty || cordicBound(cordicUnits) <= ii,
    s"schedule.cordic-units = $cordicUnits cannot compute ${angles.size} sin/cos pairs in " +
      s"schedule.clocks-per-sample = $ii clocks; use cordic-units >= ${ceilDiv(angles.size, ii)} or " +
      s"clocks-per-sample >= ${cordicBound(cordicUnits)}"
  )

  /** Whether a unit's result is captured in a register (shared: the unit moves on to the next operation). */
  val capturesCordic: Boolean = ii > 1 || cordicUnits < angles.size

  /** Clocks from a multiply's issue to its value in a register. */
  def mulLatency(id: NodeId): Int = {
    val rounds = analysis.productRounding(id).rounding != Rounding.Truncate
    val capture = if (!dedicated || rounds) 1 else 0
    if (shiftAdded(id)) ShiftAddMultiplier.latency(shiftAddOperands(id)._2) + capture
    else {
      val shape = if (dedicated) shapeOf(id) else classes(classOf(id)).shape
      PipelinedMultiplier.latency(shape.wide, shape.narrow) + multiplierLatency - 1 + capture +
        (if (routed) Schedule.routeStages else 0)
    }
  }

  /** Clocks from an angle's issue (its sum read from the input register) to sin/cos in registers. */
  val trigLatency: Int = 1 + cordic.latency + (if (capturesCordic) 1 else 0)

  /**
   * The first cycle from `earliest` whose residue has a free unit among `units` (multipliers or CORDIC
   * units).
   */
  private def place(taken: Set[(Boolean, Int, Int)], isMul: Boolean, units: Range, earliest: Int): Slot =
    Iterator
      .from(earliest)
      .flatMap(r => units.find(u => !taken((isMul, u, r % ii))).map(u => Slot(Some(u), r)))
      .next()

  /**
   * The order the list scheduler places the nodes in: the graph's, or for registers storage with list order
   * by-height the longest chain of latencies to an output first (a topological order: every operation is
   * higher than its users, and a leaf as high as its highest user comes first, by index), so the critical
   * path claims the units' residues before the operations with slack.
   */
  private val placementOrder: IndexedSeq[NodeId] =
    if (request.stored != Storage.Registers || !request.listOrder.contains(ListOrder.ByHeight)) ids
    else ids.sortBy(id => (-height(id.index), id.index))

  /** Each node's longest chain of latencies to an output, its own latency included. */
  private lazy val height: Map[Int, Int] = {
    val users = ids.flatMap(id => graph(id).operands.map(_.index -> id.index)).groupMap(_._1)(_._2)
    ids.reverse.foldLeft(Map.empty[Int, Int]) { (h, id) =>
      h + (id.index -> (ownLatency(id) + users.getOrElse(id.index, Nil).map(h).maxOption.getOrElse(0)))
    }
  }

  /** Clocks from an operation's issue to its value in a register (a literal or an input: none). */
  private def ownLatency(id: NodeId): Int = graph(id) match {
    case _: Mul              => mulLatency(id)
    case _: Trig             => trigLatency
    case _: Const | _: Input => 0
    case _                   => 1
  }

  /**
   * The latency the dependences alone allow: every operation at its operands' ready cycle (a forwardable
   * product read off its unit a cycle early), a unit free whenever asked, angles read from cycle 1, each
   * accumulated tree's products in cycles of their own as early as they can be (its sums then need not wait
   * for the graph's order of additions: an accumulator reassociates its tree); plus the output stage. The
   * report prints it beside the achieved latency: the distance the list schedule adds.
   */
  lazy val dependenceBound: Int = lastOutput(unitsUnbounded(earliestRead, accumulationOf)) + outputStages

  /**
   * Each node's ready cycle with a unit free whenever asked and angles read from cycle 1 (a literal: none);
   * an addition reads operand `x`, ready in `r`, in `read(x, r)`; the root of a tree in `accumulated` is
   * ready [[Accumulation.rootDelay]] after its products, each in a cycle of its own, the earliest first.
   */
  private def unitsUnbounded(
      read: (NodeId, Int) => Int,
      accumulated: Map[NodeId, Accumulation] = Map.empty
  ): Vector[Option[Int]] =
    ids.foldLeft(Vector.empty[Option[Int]]) { (r, id) =>
      def at(x: NodeId) = r(x.index).getOrElse(0)
      r :+ (graph(id) match {
        case Const(_)       => None
        case Input(_)       => Some(inputCycle)
        case Trig(_, angle) => Some(angleEarliest(angle) + ownLatency(id))
        case op @ Mul(_, _) => Some(op.operands.map(at).max + ownLatency(id))
        case _: Add | _: Sub if accumulated.get(id).exists(_.root == id) =>
          val last = accumulated(id).products.map(at).sorted.reduceLeft((prev, p) => math.max(p, prev + 1))
          Some(last + Accumulation.rootDelay)
        case op => Some(op.operands.map(x => read(x, at(x))).max + ownLatency(id))
      })
    }

  /** The cycle the last output is ready in, given each node's `ready` cycle. */
  private def lastOutput(ready: Vector[Option[Int]]): Int =
    graph.outputs.flatMap(o => ready(o.node.index)).maxOption.getOrElse(inputCycle)

  /**
   * Clocks each node can be late, units free and no product forwarded, before the last output is: 0 on a
   * longest path of the dependences. `schedule.forward-slack` forwards the products within it.
   */
  private[graph] lazy val slack: IndexedSeq[Int] = {
    val ready = unitsUnbounded((_, r) => r)
    val end = lastOutput(ready)
    ids.map(id => end - ready(id.index).getOrElse(0) - (height(id.index) - ownLatency(id)))
  }

  /**
   * The trees of additions to sum by accumulators (`schedule.accumulate-slack`; registers storage at 2 clocks
   * per sample or more): their products of one class of units, at most II of them, the clocks their
   * accumulation costs ([[Accumulation.latencyCost]]) within their root's slack plus the setting. Their
   * products are never forwarded.
   */
  private lazy val accumulationCandidates: IndexedSeq[Accumulation] = request.accumulateSlack match {
    case Some(allowed) if !dedicated && request.stored == Storage.Registers =>
      Accumulation.find(graph, muls.toSet).filter { a =>
        a.terms.size <= ii && a.products.map(classOf).distinct.size == 1 &&
        Accumulation.latencyCost(a.terms.size) <= slack(a.root.index) + allowed
      }
    case _ => IndexedSeq.empty
  }
  private lazy val candidateOf: Map[NodeId, Accumulation] =
    accumulationCandidates.flatMap(a => (a.sums ++ a.products).map(_ -> a)).toMap

  /** The product of each candidate tree the list scheduler reaches last: it places the tree's products. */
  private lazy val placedWith: Map[Accumulation, NodeId] = {
    val position = placementOrder.zipWithIndex.map { case (id, k) => id -> k }.toMap
    accumulationCandidates.map(a => a -> a.products.maxBy(position)).toMap
  }

  /** A multiply at the first cycle from its operands' ready cycle with a unit of its class free. */
  private def placeMul(s: ScheduleState, id: NodeId): ScheduleState = {
    val earliest = graph(id).operands.map(x => s.ready(x.index).getOrElse(0)).max
    val slot = place(s.taken, isMul = true, classUnits(classOf(id)), earliest)
    s.copy(
      ready = s.ready.updated(id.index, Some(slot.issue + mulLatency(id))),
      slots = s.slots.updated(id.index, Some(slot)),
      taken = s.taken + ((true, slot.unit.get, slot.issue % ii))
    )
  }

  /**
   * An addition, subtraction or negation in the cycle its operands are ready. A shared unit's product is on
   * its output for one cycle, then captured. A product with this adder as its only reader is taken straight
   * from the unit in that cycle when the other operand is ready by then: the adder's register holds it, no
   * capture register, one cycle less.
   */
  private def placeSum(s: ScheduleState, id: NodeId): ScheduleState = {
    def at(x: NodeId) = s.ready(x.index).getOrElse(0)
    val operands = graph(id).operands
    val r = operands.map(x => earliestRead(x, at(x))).max
    val direct = operands.filter(x => forwardable(x) && earliestRead(x, at(x)) == r)
    s.copy(
      ready = s.ready.updated(id.index, Some(r + 1)),
      slots = s.slots.updated(id.index, Some(Slot(None, r))),
      forwarded = s.forwarded ++ direct
    )
  }

  /**
   * Slots for a candidate tree's products, which may issue from `earliest` on (one class of units, so one
   * latency): each at or after its own, all within II - 1 clocks of the first, so that each leaves its unit
   * in a residue of its own and one accumulator takes them all; in each cycle a unit free then, one the tree
   * already uses first (its product is then no new input of the accumulator). The slots whose last product
   * issues first, then those on the fewest units, then the earliest first cycle. None when the class has no
   * such slots.
   */
  private def chainSlots(
      taken: Set[(Boolean, Int, Int)],
      units: Range,
      earliest: IndexedSeq[Int]
  ): Option[IndexedSeq[Slot]] = {
    // earliest first: with release times, the order that ends first
    val order = earliest.indices.sortBy(earliest)
    def from(first: Int): Option[IndexedSeq[Slot]] = {
      val slots = Array.fill(earliest.size)(Slot(None, 0))
      val placed = (first until first + ii).foldLeft(0) { (j, t) =>
        if (j == order.size || t < earliest(order(j))) j
        else {
          val used = order.take(j).flatMap(slots(_).unit)
          val free = units.filterNot(u => taken((true, u, t % ii)))
          free.sortBy(u => !used.contains(u)).headOption.fold(j) { u =>
            slots(order(j)) = Slot(Some(u), t)
            j + 1
          }
        }
      }
      Option.when(placed == order.size)(slots.toIndexedSeq)
    }
    // an interval past the latest earliest cycle the free residues repeat
    (earliest.min to earliest.max + ii).iterator
      .flatMap(from)
      .minByOption(slots => (slots.map(_.issue).max, slots.flatMap(_.unit).distinct.size))
  }

  /**
   * A candidate tree's products in [[chainSlots]], the tree then accumulated: its sums ready
   * [[Accumulation.rootDelay]] after the last product would be in its own register (the accumulator's adder
   * writes the root's register then). Where the class has no such slots, each product placed as any multiply
   * and the sums as adders.
   */
  private def placeTree(s: ScheduleState, a: Accumulation): ScheduleState = {
    val earliest = a.products.map(p => graph(p).operands.map(x => s.ready(x.index).getOrElse(0)).max)
    // in graph order: operands first
    val sums = a.sums.sortBy(_.index)
    chainSlots(s.taken, classUnits(classOf(a.products.head)), earliest.toIndexedSeq) match {
      case None => sums.foldLeft(a.products.foldLeft(s)(placeMul))(placeSum)
      case Some(slots) =>
        val placed = a.products.zip(slots).foldLeft(s.copy(chains = s.chains + a)) { case (st, (p, slot)) =>
          st.copy(
            ready = st.ready.updated(p.index, Some(slot.issue + mulLatency(p))),
            slots = st.slots.updated(p.index, Some(slot)),
            taken = st.taken + ((true, slot.unit.get, slot.issue % ii))
          )
        }
        val root = a.products.zip(slots).map { case (p, slot) => slot.issue + mulLatency(p) }.max +
          Accumulation.rootDelay
        sums.foldLeft(placed)((st, x) =>
          st.copy(
            ready = st.ready.updated(x.index, Some(root)),
            slots = st.slots.updated(x.index, Some(Slot(None, root - 1)))
          )
        )
    }
  }

  private val state: ScheduleState = {
    val none = Vector.fill(ids.size)(Option.empty[Int])
    placementOrder.foldLeft(ScheduleState(none, none.map(_ => None), Set.empty, Map.empty, Set.empty)) {
      (s, id) =>
        def at(x: NodeId) = s.ready(x.index).getOrElse(0)
        def plain(ready: Option[Int], slot: Option[Slot]) =
          s.copy(ready = s.ready.updated(id.index, ready), slots = s.slots.updated(id.index, slot))
        graph(id) match {
          case Const(_) => plain(None, None)
          case Input(_) => plain(Some(inputCycle), Some(Slot(None, inputCycle - 1)))
          case Trig(_, angle) =>
            s.angleSlots.get(angle) match {
              case Some(slot) => plain(Some(slot.issue + trigLatency), Some(slot))
              case None =>
                val slot = place(s.taken, isMul = false, 0 until cordicUnits, angleEarliest(angle))
                s.copy(
                  ready = s.ready.updated(id.index, Some(slot.issue + trigLatency)),
                  slots = s.slots.updated(id.index, Some(slot)),
                  taken = s.taken + ((false, slot.unit.get, slot.issue % ii)),
                  angleSlots = s.angleSlots + (angle -> slot)
                )
            }
          case Mul(a, b) if shiftAdded(id) =>
            val issue = math.max(at(a), at(b)) // its own adder tree: no unit to wait for
            plain(Some(issue + mulLatency(id)), Some(Slot(None, issue)))
          case Mul(_, _) if candidateOf.contains(id) =>
            val a = candidateOf(id)
            if (placedWith(a) == id) placeTree(s, a) else s // with the tree's last product
          case Mul(_, _) => placeMul(s, id)
          // placed with the tree's products (a deep tree's sum may come before its last product)
          case _ if candidateOf.contains(id) => s
          case _                             => placeSum(s, id)
        }
    }
  }

  /** The trees of additions summed by accumulators: the candidates the list scheduler placed so. */
  lazy val accumulations: IndexedSeq[Accumulation] = accumulationCandidates.filter(state.chains)
  private lazy val accumulationOf: Map[NodeId, Accumulation] =
    accumulations.flatMap(a => (a.sums ++ a.products).map(_ -> a)).toMap

  /** The accumulated tree `id` is a product or a sum of. */
  def accumulation(id: NodeId): Option[Accumulation] = accumulationOf.get(id)

  /**
   * A multiply whose only reader is an addition (no other use, not an output): its reader may take the
   * product off the unit's output the cycle before it is captured. With registered routes only one whose
   * slack is within `schedule.forward-slack`: the reader is an adder, not a unit's operand multiplexer, so no
   * registered route is skipped, but each such product is a route from a unit's output with no register on
   * it, and forwarding every one made the README's UR5 route far slower (docs/timing-closure.md).
   */
  private def forwardable(x: NodeId) =
    !dedicated && graph(x).isInstanceOf[Mul] && graph.readers(x.index) == 1 && !candidateOf.contains(x) &&
      (!routed || request.forwardSlack.exists(slack(x.index) <= _))

  /**
   * The first cycle an operation may read `x`, ready (in its register) in `ready`: a cycle early if
   * forwarded.
   */
  private def earliestRead(x: NodeId, ready: Int): Int = if (forwardable(x)) ready - 1 else ready

  /** A forwardable multiply that is not an output too: the refinement may forward it to its one reader. */
  private def forwardableToReader(x: NodeId) = forwardable(x) && graph.outputs.forall(_.node != x)

  /** A multiply's operands ordered by width for its unit's ports ([[MulShape.widths]]): the wider first. */
  private def byWidth(id: NodeId): IndexedSeq[NodeId] = {
    val Mul(a, b) = graph(id): @unchecked
    if (analysis(a).format.width >= analysis(b).format.width) IndexedSeq(a, b) else IndexedSeq(b, a)
  }

  /**
   * The schedule as a [[RefinementProblem]] with the list schedule as its start (registers storage, 2 clocks
   * per sample or more): additions keep their own adders, the inputs and the sin/cos their cycles, and the
   * outputs must be ready when the list schedule has them.
   */
  lazy val refinementProblem: Option[(RefinementProblem, Refined)] =
    if (dedicated || request.stored != Storage.Registers) None
    else {
      val nodes = ids.map { id =>
        val f = analysis(id).format
        graph(id) match {
          case Const(_)              => RefineNode.Literal(f.width)
          case Input(_) | Trig(_, _) => RefineNode.Fixed(state.ready(id.index).get, f.width)
          // an accumulated tree's sums: read by nothing in the problem (its products neither), its root
          // ready when its last product leaves the unit
          case _: Add | _: Sub if accumulationOf.contains(id) =>
            RefineNode.Fixed(state.ready(id.index).get, f.width)
          case Mul(_, _) if !shiftAdded(id) =>
            val units = classUnits(classOf(id))
            val widths = byWidth(id).map(analysis(_).format.width)
            RefineNode.Shared(
              byWidth(id).map(_.index),
              mulLatency(id),
              f.width,
              units,
              swappable = widths.forall(_ <= unitShapes(units.head).narrow),
              forwardable = forwardableToReader(id),
              chained = accumulationOf
                .get(id)
                .map(a => Chained(a.root.index, analysis(a.root).format.width)),
              memory = request.productMemories && !accumulationOf.contains(id) && truncated(id)
            )
          case op =>
            val latency = state.ready(id.index).get - state.slots(id.index).get.issue
            RefineNode.Own(
              op.operands.map(_.index).toIndexedSeq,
              latency,
              f.width,
              forwardable = forwardableToReader(id),
              takesForwarded = !shiftAdded(id)
            )
        }
      }
      val problem = RefinementProblem(
        ii,
        nodes,
        graph.outputs.map(_.node.index),
        lastOutput(state.ready),
        unitShapes(_).widths,
        LogicCost.muxBit,
        LogicCost.heldBit,
        memoryDelayMinCycles,
        LogicCost.blockRamTap
      )
      val start = Refined(
        ids.map(id => state.slots(id.index).fold(-1)(_.issue)),
        ids.map(id =>
          if (nodes(id.index).isInstanceOf[RefineNode.Shared]) state.slots(id.index).get.unit.get else -1
        ),
        ids.map(_ => false)
      )
      Some((problem, start))
    }

  /**
   * The shortest schedule the solver finds from the list schedule (`schedule.scheduler = cp-sat`, registers
   * storage at 2 clocks per sample or more); None where it finds none shorter.
   */
  lazy val shorter: Option[ShorterSchedule] =
    refinementProblem.filter(_ => request.scheduler == Scheduler.CpSat).flatMap { case (problem, list) =>
      LatencySearch(problem, list)
    }

  /** The cycle every output is in its register under `readyAt` (no output: the input cycle). */
  private def lastOutput(readyAt: IndexedSeq[Option[Int]]): Int =
    graph.outputs.flatMap(o => readyAt(o.node.index)).maxOption.getOrElse(inputCycle)

  /** The list schedule's latency, before any solver or refinement moved it (for reports). */
  def listLatency: Int = lastOutput(state.ready) + outputStages

  /**
   * The schedule refined (`request.refinement` > 0): issue cycles, units and port order moved so that the
   * operand multiplexers and the held registers take the fewest logic elements, at no more latency, from the
   * solver's shorter schedule or else the list schedule's; without refinement, the solver's as it is.
   */
  private lazy val refined: Option[Refined] =
    refinementProblem.flatMap { case (listProblem, list) =>
      val (problem, start) =
        shorter.fold((listProblem, list))(s => (s.problem, s.solution))
      val movable = problem.nodes.count {
        case _: RefineNode.Own | _: RefineNode.Shared => true
        case _                                        => false
      }
      if (request.refinement > 0)
        Some(problem.anneal(start, request.refinement.toLong * movable, Schedule.refinementSeed))
      else shorter.map(_ => start)
    }

  /** The cycle an operation reads its operands (its unit may still be rebound: see `slot`). */
  private def issue(id: NodeId): Int = graph(id) match {
    case _ if isAccumulatedSum(id) => ready(id.index).get - 1
    case Input(_) | Trig(_, _)     => state.slots(id.index).get.issue // fixed in the refinement's problem
    case _                         => refined.fold(state.slots(id.index).get.issue)(_.issue(id.index))
  }

  /**
   * A sum of an accumulated tree: its register (the root's) is written as the accumulator takes the last
   * product.
   */
  private def isAccumulatedSum(id: NodeId) = accumulationOf.get(id).exists(_.sums.contains(id))

  /** Cycle from which each node's value of the current sample is in its register (None: a constant). */
  lazy val ready: IndexedSeq[Option[Int]] = refined match {
    case None => state.ready
    case Some(r) =>
      val moved = ids.map { id =>
        graph(id) match {
          case Const(_)                  => None
          case Input(_) | Trig(_, _)     => state.ready(id.index)
          case _ if isAccumulatedSum(id) => None // from its products, below
          case _ => Some(r.issue(id.index) + state.ready(id.index).get - state.slots(id.index).get.issue)
        }
      }
      ids.map(id =>
        if (isAccumulatedSum(id))
          Some(accumulationOf(id).products.map(p => moved(p.index).get).max + Accumulation.rootDelay)
        else moved(id.index)
      )
  }
  def apply(id: NodeId): Option[Int] = ready(id.index)

  /**
   * Multiplies whose only reader takes the product from the unit's output in the cycle before `ready`: they
   * have no register.
   */
  private lazy val forwardedSet: Set[NodeId] = refined match {
    case None => state.forwarded
    case Some(r) =>
      ids
        .filter(x =>
          forwardableToReader(x) && {
            val reader = ids.find(id => graph(id).operands.contains(x)).get
            !graph(reader).isInstanceOf[Mul] && r.issue(reader.index) == ready(x.index).get - 1
          }
        )
        .toSet
  }
  def forwarded(id: NodeId): Boolean = forwardedSet(id)

  /**
   * A multiply's operands in the order of its unit's ports ([[MulShape.widths]]): the wider first (the first
   * on a tie), unless the refinement swapped them.
   */
  def ports(id: NodeId): IndexedSeq[NodeId] =
    if (refined.exists(_.swapped(id.index))) byWidth(id).reverse else byWidth(id)

  /**
   * What a unit's port reads for operand `x` of an operation issued in cycle `issue`, each value in its own
   * registers (the binding's view: registers are shared after it).
   */
  def portSource(x: NodeId, issue: Int): PortSource =
    if (isConst(x)) PortSource.Literal(x) else PortSource.Held(x, (issue - ready(x.index).get) / ii)

  /**
   * The input of a unit port's multiplexer for operand `x` of an operation issued in cycle `issue`: its
   * [[portSource]], or for a product in a [[SharedRegister]] the first member of its width (members of one
   * width are the same bits of the same register, so one input).
   */
  def muxSource(x: NodeId, issue: Int): PortSource = (portSource(x, issue), sharedRegisterOf.get(x)) match {
    case _ if sinCosMemoryOf.contains((x, issue)) => PortSource.SinCosWord(sinCosMemoryOf((x, issue)))
    case (PortSource.Held(_, 0), Some(shared)) =>
      val width = analysis(x).format.width
      PortSource.Held(shared.members.find(analysis(_).format.width == width).get, 0)
    case (source, _) => source
  }

  /**
   * A product whose way out of its unit is settled before the product memories and then the shared registers
   * choose theirs: forwarded, accumulated, or in a register of its own that readers' copies are loaded from.
   */
  private def settledEarlier(id: NodeId): Boolean =
    forwarded(id) || accumulationOf.contains(id) || readerCopies.contains(id)

  /**
   * Registers that products of one unit take turns in (`schedule.share-registers`; registers storage at 2
   * clocks per sample or more): the products on the units, each with a register (not forwarded, accumulated,
   * copied for readers or in a product memory), read only within the interval after it is ready. The product
   * memories choose first: a member takes no register at all, where sharing saves part of one.
   */
  lazy val sharedRegisters: IndexedSeq[SharedRegister] =
    if (!request.shareRegisters || dedicated || request.stored != Storage.Registers) IndexedSeq.empty
    else
      SharedRegister.allocate(
        ii,
        muls
          .filterNot(id => settledEarlier(id) || productMemoryOf.contains(id))
          .flatMap { id =>
            val rule = analysis.productRounding(id)
            val t = ready(id.index).get
            reads(id.index).maxOption
              .filter(_ - t < ii)
              .map(last =>
                SharedRegister.Candidate(
                  id,
                  slot(id).get.unit.get,
                  rule.drop,
                  rule.rounding,
                  analysis(id).format.width,
                  t,
                  last
                )
              )
          }
      )
  lazy val sharedRegisterOf: Map[NodeId, SharedRegister] =
    sharedRegisters.flatMap(r => r.members.map(_ -> r)).toMap

  /**
   * Block RAMs units write their products into (`schedule.product-memories`; registers storage at 2 clocks
   * per sample or more): truncated products, each with a register of its own otherwise (not forwarded,
   * accumulated or copied for readers), read from the memory when its read port allows; the shared registers
   * take from those left.
   */
  lazy val productMemories: IndexedSeq[ProductMemory] =
    if (!request.productMemories || dedicated || request.stored != Storage.Registers) IndexedSeq.empty
    else
      ProductMemory.allocate(
        ii,
        muls
          .filterNot(settledEarlier)
          .filter(id => truncated(id) && reads(id.index).nonEmpty)
          .map { id =>
            val unit = slot(id).get.unit.get
            ProductMemory.Candidate(
              id,
              unit,
              analysis.productRounding(id).drop,
              analysis(id).format.width,
              unitShape(unit).productBits,
              ready(id.index).get,
              reads(id.index)
            )
          }
      )

  /** A product its unit's memory may hold: truncated, so a slice of the word is what its register holds. */
  private def truncated(id: NodeId): Boolean = analysis.productRounding(id).rounding == Rounding.Truncate

  lazy val productMemoryOf: Map[NodeId, ProductMemory] =
    productMemories.flatMap(m => m.members.map(_.id -> m)).toMap

  /**
   * Block RAMs the CORDIC units write their sines and cosines into (`schedule.sin-cos-memories`; registers
   * storage at 2 clocks per sample or more): every read of a sin or cos within [[SinCosMemory.inWindow]], the
   * reads of one multiplier port kept together where they can be (after the binding: no cycle or unit moves).
   */
  lazy val sinCosMemories: IndexedSeq[SinCosMemory] =
    if (!request.sinCosMemories || dedicated || request.stored != Storage.Registers) IndexedSeq.empty
    else {
      val trigReads = for {
        id <- ids
        Trig(fn, angle) <- Seq(graph(id))
        t = ready(id.index).get
        c <- reads(id.index)
        if SinCosMemory.inWindow(t, c)
      } yield SinCosMemory.Read(angleSlot(angle).unit.get, fn, id, t, c)
      val mulPorts: Map[(NodeId, Int), Seq[SinCosMemory.MulPort]] = (for {
        (bound, u) <- mulBindings.zipWithIndex
        (_, id) <- bound
        (x, k) <- ports(id).zipWithIndex
      } yield (x, issue(id)) -> SinCosMemory.MulPort(u, k)).groupMap(_._1)(_._2)
      SinCosMemory.allocate(ii, trigReads, r => mulPorts.getOrElse((r.value, r.cycle), Nil))
    }

  /** The [[sinCosMemories]] index serving each read (value, cycle) they take. */
  lazy val sinCosMemoryOf: Map[(NodeId, Int), Int] =
    sinCosMemories.zipWithIndex.flatMap { case (m, k) => m.reads.map(r => (r.value, r.cycle) -> k) }.toMap

  /**
   * The cycles a node is read in from its own registers: [[reads]] but those a [[SinCosMemory]] serves (a sin
   * or cos read only from memories has no register).
   */
  def ownReads(id: NodeId): Seq[Int] =
    if (sinCosMemories.isEmpty) reads(id.index)
    else reads(id.index).filterNot(c => sinCosMemoryOf.contains((id, c)))

  /**
   * Each shared multiply's unit: the refinement's, or with registers storage the list scheduler's (the
   * solver's) binding improved so that the units' operand multiplexers have the fewest inputs
   * ([[BindingProblem]]; no cycle changes); dedicated units and memory storage (whose banks are bound with
   * the units) keep the scheduler's.
   */
  private lazy val boundUnit: Map[NodeId, Int] =
    if (dedicated || request.stored != Storage.Registers) Map.empty
    else
      refined.filter(_ => request.refinement > 0) match {
        case Some(r) => muls.map(id => id -> r.unit(id.index)).toMap
        case None =>
          val problem = BindingProblem(
            muls.map(id =>
              BindOp(classUnits(classOf(id)), issue(id) % ii, ports(id).map(portSource(_, issue(id))))
            ),
            unitShapes(_).widths
          )
          muls
            .zip(
              problem.best(muls.map(id => refined.fold(state.slots(id.index).get.unit.get)(_.unit(id.index))))
            )
            .toMap
      }

  /** Each node's issue: the cycle it reads its operands, and its unit. */
  def slot(id: NodeId): Option[Slot] =
    state.slots(id.index).map(sl => Slot(boundUnit.get(id).orElse(sl.unit), issue(id)))

  /** Each angle's CORDIC unit and issue cycle. */
  def angleSlot(angle: AngleSum): Slot = state.angleSlots(angle)

  /** Cycle at which every output is in its register: the output stage reads them then. */
  lazy val outputsReady: Int = lastOutput(ready)

  /**
   * Registers of the output stage: [[Schedule.outputStages]], or with registered routes memory storage's
   * three ([[BankedSchedule.outputStages]]: the OR of every torque's saturation then has a clock of its own).
   */
  def outputStages: Int = if (routed) BankedSchedule.outputStages else Schedule.outputStages

  /** Cycles from a sample on the input port to its torques on the output port (output stage included). */
  lazy val latency: Int = outputsReady + outputStages

  /** Cycles at which each node is read: by its users at their issue, and by the output stage. */
  lazy val reads: IndexedSeq[Seq[Int]] = {
    val byUsers = ids.flatMap(id => graph(id).operands.map(x => x.index -> issue(id)))
    val byOutputs = graph.outputs.map(o => o.node.index -> outputsReady)
    val all = (byUsers ++ byOutputs).groupMap(_._1)(_._2)
    ids.map(id => all.getOrElse(id.index, Nil).distinct.sorted)
  }

  /**
   * Cycles at which joint `j`'s angle is read from the input register: by the angle sums that contain it,
   * [[angleSumStages]] before their issue.
   */
  def angleReads(j: Int): Seq[Int] =
    angles.filter(_.joints.contains(j)).map(a => angleSlot(a).issue - angleSumStages(a)).distinct.sorted

  /**
   * `schedule.reader-copies` (registered routes): for each value in a register of its own (not forwarded; a
   * product so copied keeps its register: no product memory or shared register takes it) that several
   * multiplier units read within the interval after it is ready, the units that read it through a copy of
   * that register, loaded a clock after it (so the copy holds the value from ready + 1 to ready + II). Every
   * such unit gets one but the unit left on the register itself: one that reads the value when it is ready (a
   * copy has it a clock later), else the one with the most reads; a second unit reading it when ready stays
   * on the register too. A register read by units the placer puts apart crossed the die to the far one (the
   * Panda's limit: docs/timing-closure.md); each copy is placed beside its own unit's multiplexers.
   */
  lazy val readerCopies: Map[NodeId, Set[Int]] =
    if (!request.readerCopies || !routed) Map.empty
    else {
      val early = for {
        (bound, u) <- mulBindings.zipWithIndex
        (_, id) <- bound
        x <- ports(id)
        if !isConst(x) && !forwarded(x)
        if !graph(x).isInstanceOf[Trig] || capturesCordic
        offset = issue(id) - ready(x.index).get
        if offset < ii && !sinCosMemoryOf.contains((x, issue(id)))
      } yield (x, u, offset)
      early
        .groupBy(_._1)
        .view
        .flatMap { case (x, reads) =>
          val byUnit = reads.groupMap(_._2)(_._3)
          val home = byUnit.find(_._2.contains(0)).getOrElse(byUnit.maxBy(r => (r._2.size, -r._1)))._1
          val copied = byUnit.collect { case (u, offsets) if u != home && !offsets.contains(0) => u }.toSet
          Option.when(copied.nonEmpty)(x -> copied)
        }
        .toMap
    }

  /** Copies [[readerCopies]] builds, all values together. */
  def readerCopyCount: Int = readerCopies.values.map(_.size).sum

  /**
   * Whether unit `u` takes operand `x` of an operation issued in cycle `issue` from its copy of `x`'s
   * register ([[readerCopies]]): a read within the interval after `x` is ready (later reads take the chain's
   * stages).
   */
  def readsCopy(x: NodeId, u: Int, issue: Int): Boolean =
    issue - ready(x.index).get < ii && readerCopies.get(x).exists(_.contains(u)) &&
      !sinCosMemoryOf.contains((x, issue))

  /** Multiplies bound to each multiplier unit, with their residues. */
  lazy val mulBindings: IndexedSeq[Seq[(Int, NodeId)]] = {
    val bound =
      muls.map(id => slot(id).get).zip(muls).groupMap(_._1.unit.get) { case (sl, id) => (sl.issue % ii, id) }
    (0 until multiplierUnits).map(u => bound.getOrElse(u, Nil).sortBy(_._1))
  }

  /**
   * The distinct sources of each port of unit `u` (wide, narrow), in the order its operations first read
   * them: its operand multiplexers' inputs (one at II = 1).
   */
  def portSources(u: Int): IndexedSeq[Seq[PortSource]] =
    IndexedSeq(0, 1).map(k =>
      mulBindings(u).map { case (_, id) => muxSource(ports(id)(k), issue(id)) }.distinct
    )

  /** Angles bound to each CORDIC unit, with their residues. */
  val cordicBindings: IndexedSeq[Seq[(Int, AngleSum)]] = {
    val bound = angles.groupMap(a => angleSlot(a).unit.get)(a => (angleSlot(a).issue % ii, a))
    (0 until cordicUnits).map(u => bound.getOrElse(u, Nil).sortBy(_._1))
  }

  /** Register bits that hold values between their cycles (stage chains, see the hardware), for reports. */
  def heldBits: Long = ids
    .filterNot(forwarded)
    .map { id =>
      val last = ownReads(id).maxOption
      (apply(id), last) match {
        case (Some(t), Some(l)) =>
          (if (ii == 1) (l - t + 1).toLong else ((l - t) / ii + 1).toLong) * analysis(id).format.width
        case _ => 0L
      }
    }
    .sum

  /**
   * The fewest clocks per sample any schedule of these operations could have within `budget` 18x18 blocks,
   * for the report beside the achieved interval: every variable product occupies its operands' blocks for one
   * clock (perfect packing, no per-class units, no memory port limits), a CORDIC unit takes one angle per
   * clock and its own blocks, and the number of CORDIC units is the best for the bound. None when the budget
   * cannot hold a CORDIC unit and a product at once.
   */
  def clocksLowerBound(budget: Int): Option[Int] = {
    val blockSlots = muls.map(id => shapeOf(id).blocks).sum
    def at(cordics: Int): Option[Int] = {
      val forProducts = budget - cordics * requestedCordic.multiplierBlocks
      if (forProducts <= 0 && blockSlots > 0) None
      else
        Some(
          math.max(
            if (cordics == 0) 1 else ceilDiv(angles.size, cordics),
            if (blockSlots == 0) 1 else ceilDiv(blockSlots, forProducts)
          )
        )
    }
    (if (angles.isEmpty) Seq(0) else 1 to angles.size).flatMap(at).minOption
  }

  /** Multiplies on multiplier blocks per sample (every multiply but the shift-and-add ones). */
  def blockMultiplies: Int = muls.size

  /**
   * Multiplies on blocks per sample over the multiplier units' slots per sample (units x clocks per sample).
   */
  def multiplierUtilization: Double =
    if (multiplierUnits == 0) 0.0 else blockMultiplies.toDouble / (multiplierUnits.toLong * ii)

  /** Samples per second at a clock of `hz`. */
  def samplesPerSecond(hz: Double): Double = hz / ii
}

object Schedule {

  /** The refinement's seed: the same schedule every run. */
  val refinementSeed: Long = 1L

  /**
   * Registers of the output stage, after every output is ready: each torque rounded and saturated on its own,
   * then every joint's flag combined with every torque's saturation (memory storage has one more:
   * [[BankedSchedule.outputStages]]).
   */
  val outputStages: Int = 2

  /**
   * Clocks a multiply on a shared unit takes more with `datapath.registered-routes`: its operands pass two
   * registered multiplexer levels (the first beside each group of sources, the second beside the unit). Its
   * product travels from the unit's last adder register to the registers of its readers (a register between
   * cost a clock per multiply and did not move the clock: docs/timing-closure.md).
   */
  val routeStages: Int = 2

  /**
   * `datapath.registered-routes = auto`: routes pass registers above this many clocks per sample. Up to 4
   * sources an operand multiplexer is one slice, and planar3's device fit at 3 clocks routes direct, limited
   * by a multiplier block rather than a route between units; the UR5's at 17 and 18 clocks, multiplexers of
   * up to 17-18 sources spread across the chip, did not route at all (docs/timing-closure.md).
   */
  val directMaxClocks: Int = 4

  /** The first cycle an angle sum can be read: the joints' angles are in the input register from cycle 1. */
  val firstAngleCycle: Int = 1
}
