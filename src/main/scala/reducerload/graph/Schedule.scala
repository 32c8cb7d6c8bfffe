package reducerload.graph

import reducerload.fixedpoint.Rounding
import reducerload.load.TimedArith
import reducerload.pipeline.PipelinedMultiplier

/**
 * What a user asks of the schedule; `None` means derive it.
 *
 * @param clocksPerSample the initiation interval: a new sample may enter every this many clocks (None: `auto`, the fewest the budget allows)
 * @param maxMultipliers  18x18 multiplier blocks the datapath may use (None: no budget)
 * @param cordicUnits     sin/cos units (None: the fewest that do not lengthen the interval)
 */
final case class ScheduleRequest(clocksPerSample: Option[Int] = Some(1), maxMultipliers: Option[Int] = None, cordicUnits: Option[Int] = None) {
  require(clocksPerSample.forall(c => c >= 1 && c <= 4096), s"schedule.clocks-per-sample must be auto or in 1..4096, got ${clocksPerSample.get}")
  require(maxMultipliers.forall(m => m >= 1 && m <= 100000), s"schedule.max-multipliers must be none or in 1..100000, got ${maxMultipliers.get}")
  require(cordicUnits.forall(c => c >= 1 && c <= 4096), s"schedule.cordic-units must be auto or in 1..4096, got ${cordicUnits.get}")
}

/** Operand widths of a multiplier unit, wider operand first: its 18x18 blocks and its pipeline depth follow. */
final case class MulShape(wide: Int, narrow: Int) {
  def blocks: Int = PipelinedMultiplier.blocks(wide, narrow)
  def max(o: MulShape): MulShape = MulShape(math.max(wide, o.wide), math.max(narrow, o.narrow))
  override def toString: String = s"${wide}x$narrow"
}
object MulShape {
  def of(a: Int, b: Int): MulShape = MulShape(math.max(a, b), math.min(a, b))
}

/** Where and when an operation runs: its unit (multiplies and sin/cos only) and the cycle it reads its operands. */
final case class Slot(unit: Option[Int], issue: Int)

/** The list scheduler's state after each node: ready cycles, issues, occupied (is multiplier, unit, residue), angles placed. */
private final case class ScheduleState(ready: Vector[Option[Int]], slots: Vector[Option[Slot]], taken: Set[(Boolean, Int, Int)], angleSlots: Map[AngleSum, Slot])

/**
 * Modulo schedule of a graph: a sample enters every `clocksPerSample` clocks (the initiation
 * interval II) and the samples in flight share multiplier units and CORDIC units, each unit taking
 * at most one operation per residue of the cycle modulo II; additions, subtractions and negations
 * are each their own adder (an adder costs about what a shared adder's operand multiplexers would).
 * Cycles are counted from the clock a sample is taken on the input port (cycle 0). The bit-accurate
 * model does not depend on any of this: the numerics stay on the graph's nodes.
 *
 * List scheduling in the graph's order (RNEA's own order, which keeps few values alive): each
 * operation at its operands' ready cycle or, for a multiply, at the first later cycle whose residue
 * has a free unit. The graph has no recurrence, so every II at or above the resource bound is met.
 * `clocksPerSample = 1` with no budget gives every operation its own operator: the ASAP schedule.
 *
 * Timing of one operation issued (reading its operands) in cycle r:
 *  - add/sub/neg: result registered, ready at r + 1;
 *  - multiply: the unit's pipelined multiplier ([[TimedArith.mulLatency]] without rounding) then,
 *    when units are shared or the product rounds, a register that captures it: ready at
 *    r + multiplier latency (+ 1);
 *  - sin/cos of an angle sum: the sum registered, then the CORDIC unit, then (shared) a capture register.
 * Every value is held in a chain of registers written once per sample (see `stages`).
 *
 * @param inputCycle cycle at which the clamped velocities and accelerations are in registers (their
 *                   raw codes and the angles are in the input register from cycle 1)
 */
final class Schedule(val analysis: Analysis, val request: ScheduleRequest, cordicLatency: Int, multiplierLatency: Int, val inputCycle: Int) {
  import Op._
  private val graph = analysis.graph
  private val ids = graph.ids
  private val muls: IndexedSeq[NodeId] = ids.filter(graph(_).isInstanceOf[Mul])
  private val angles = graph.angles.toIndexedSeq

  /** Operand shape of a multiply. */
  def shapeOf(id: NodeId): MulShape = {
    val Mul(a, b) = graph(id): @unchecked
    MulShape.of(analysis(a).format.width, analysis(b).format.width)
  }

  /** The widest operand shape of any multiply: every shared unit is built this wide. */
  val widestShape: MulShape = muls.map(shapeOf).reduceOption(_ max _).getOrElse(MulShape(2, 2))

  private def ceilDiv(a: Int, b: Int) = (a + b - 1) / b

  /** Blocks of `units` multiplier units at interval `ii`: dedicated units are each their own op's shape. */
  private def blocksFor(ii: Int, units: Int): Int =
    if (ii == 1 && units >= muls.size) muls.map(shapeOf(_).blocks).sum else units * widestShape.blocks

  /** Shortest interval the CORDIC units allow. */
  private def cordicBound(units: Int): Int = ceilDiv(angles.size, units)

  /** The initiation interval: asked, or the fewest clocks the multiplier budget and CORDIC units allow. */
  val clocksPerSample: Int = request.clocksPerSample.getOrElse {
    val byCordic = request.cordicUnits.map(cordicBound).getOrElse(1)
    request.maxMultipliers match {
      case None => byCordic
      case Some(budget) =>
        require(muls.isEmpty || budget >= widestShape.blocks,
          s"schedule.max-multipliers = $budget is below one multiplier of the widest product ($widestShape bits: ${widestShape.blocks} blocks); " +
            s"use at least ${widestShape.blocks}")
        val units = if (muls.isEmpty) 1 else budget / widestShape.blocks
        val byBudget = if (muls.nonEmpty && blocksFor(1, muls.size) <= budget) 1 else ceilDiv(muls.size, units)
        math.max(byBudget, byCordic)
    }
  }
  private val ii = clocksPerSample

  /** Multiplier units: one per multiply at II = 1, else the fewest that fit every multiply in II slots. */
  val multiplierUnits: Int = if (ii == 1) muls.size else ceilDiv(muls.size, ii)

  /** Whether each multiply has its own unit (II = 1: no operand multiplexers, no capture register unless it rounds). */
  val dedicated: Boolean = ii == 1

  /** 18x18 blocks the multiplier units use. */
  val multiplierBlocks: Int = blocksFor(ii, multiplierUnits)

  request.maxMultipliers.foreach { budget =>
    val fewest = if (muls.isEmpty) 1 else math.max(1, (1 to 4096).find(c => blocksFor(c, if (c == 1) muls.size else ceilDiv(muls.size, c)) <= budget).getOrElse(4096))
    require(multiplierBlocks <= budget,
      s"schedule.max-multipliers = $budget is below the $multiplierBlocks blocks that schedule.clocks-per-sample = $ii needs " +
        s"(${muls.size} multiplies on $multiplierUnits units of $widestShape bits); use clocks-per-sample >= $fewest or max-multipliers >= $multiplierBlocks")
  }

  /** CORDIC units: asked, or the fewest that keep the interval. */
  val cordicUnits: Int = request.cordicUnits.getOrElse(math.max(1, ceilDiv(angles.size, ii)))
  require(angles.isEmpty || cordicBound(cordicUnits) <= ii,
    s"schedule.cordic-units = $cordicUnits cannot compute ${angles.size} sin/cos pairs in schedule.clocks-per-sample = $ii clocks; " +
      s"use cordic-units >= ${ceilDiv(angles.size, ii)} or clocks-per-sample >= ${cordicBound(cordicUnits)}")

  /** Whether a unit's result is captured in a register (shared: the unit moves on to the next operation). */
  val capturesCordic: Boolean = ii > 1 || cordicUnits < angles.size

  /** Clocks from a multiply's issue to its value in a register. */
  def mulLatency(id: NodeId): Int = {
    val Mul(a, b) = graph(id): @unchecked
    val rounds = analysis.productRounding(analysis(a).format.fracBits, analysis(b).format.fracBits).rounding != Rounding.Truncate
    val shape = if (dedicated) shapeOf(id) else widestShape
    TimedArith.mulLatency(shape.wide, shape.narrow, multiplierLatency, Rounding.Truncate) +
      (if (!dedicated || rounds) 1 else 0)
  }

  /** Clocks from an angle's issue (its sum read from the input register) to sin/cos in registers. */
  val trigLatency: Int = 1 + cordicLatency + (if (capturesCordic) 1 else 0)

  /** The first cycle from `earliest` whose residue has a free unit among `units` (multipliers or CORDIC units). */
  private def place(taken: Set[(Boolean, Int, Int)], isMul: Boolean, units: Int, earliest: Int): Slot =
    Iterator.from(earliest).flatMap(r => (0 until units).find(u => !taken((isMul, u, r % ii))).map(u => Slot(Some(u), r)))
      .next()

  private val state: ScheduleState = ids.foldLeft(ScheduleState(Vector.empty, Vector.empty, Set.empty, Map.empty)) { (s, id) =>
    def at(x: NodeId) = s.ready(x.index).getOrElse(0)
    def plain(ready: Option[Int], slot: Option[Slot]) = s.copy(ready = s.ready :+ ready, slots = s.slots :+ slot)
    graph(id) match {
      case Const(_)  => plain(None, None)
      case Input(_)  => plain(Some(inputCycle), Some(Slot(None, inputCycle - 1)))
      case Trig(_, angle) =>
        s.angleSlots.get(angle) match {
          case Some(slot) => plain(Some(slot.issue + trigLatency), Some(slot))
          case None =>
            // The angle's joints are in the input register from cycle 1.
            val slot = place(s.taken, isMul = false, cordicUnits, 1)
            s.copy(ready = s.ready :+ Some(slot.issue + trigLatency), slots = s.slots :+ Some(slot),
              taken = s.taken + ((false, slot.unit.get, slot.issue % ii)), angleSlots = s.angleSlots + (angle -> slot))
        }
      case Mul(a, b) =>
        val earliest = math.max(at(a), at(b))
        val slot = place(s.taken, isMul = true, multiplierUnits, earliest)
        s.copy(ready = s.ready :+ Some(slot.issue + mulLatency(id)), slots = s.slots :+ Some(slot),
          taken = s.taken + ((true, slot.unit.get, slot.issue % ii)))
      case op =>
        val r = op.operands.map(at).max
        plain(Some(r + 1), Some(Slot(None, r)))
    }
  }

  /** Cycle from which each node's value of the current sample is in its register (None: a constant). */
  val ready: IndexedSeq[Option[Int]] = state.ready
  def apply(id: NodeId): Option[Int] = ready(id.index)

  /** Each node's issue: the cycle it reads its operands, and its unit. */
  def slot(id: NodeId): Option[Slot] = state.slots(id.index)

  /** Each angle's CORDIC unit and issue cycle. */
  def angleSlot(angle: AngleSum): Slot = state.angleSlots(angle)

  /** Cycle at which every output is in its register: the output stage reads them then. */
  val outputsReady: Int = graph.outputs.flatMap(o => apply(o.node)).maxOption.getOrElse(inputCycle)

  /** Cycles from a sample on the input port to its torques on the output port (output stage included). */
  val latency: Int = outputsReady + 1

  /** Cycles at which each node is read: by its users at their issue, and by the output stage. */
  val reads: IndexedSeq[Seq[Int]] = {
    val byUsers = ids.flatMap(id => graph(id).operands.map(x => x.index -> slot(id).get.issue))
    val byOutputs = graph.outputs.map(o => o.node.index -> outputsReady)
    val all = (byUsers ++ byOutputs).groupMap(_._1)(_._2)
    ids.map(id => all.getOrElse(id.index, Nil).distinct.sorted)
  }

  /** Cycles at which joint `j`'s angle is read from the input register: by the angle sums that contain it. */
  def angleReads(j: Int): Seq[Int] = angles.filter(_.joints.contains(j)).map(a => angleSlot(a).issue).distinct.sorted

  /** Multiplies bound to each multiplier unit, with their residues. */
  val mulBindings: IndexedSeq[Seq[(Int, NodeId)]] = {
    val bound = muls.map(id => slot(id).get).zip(muls).groupMap(_._1.unit.get) { case (sl, id) => (sl.issue % ii, id) }
    (0 until multiplierUnits).map(u => bound.getOrElse(u, Nil).sortBy(_._1))
  }

  /** Angles bound to each CORDIC unit, with their residues. */
  val cordicBindings: IndexedSeq[Seq[(Int, AngleSum)]] = {
    val bound = angles.groupMap(a => angleSlot(a).unit.get)(a => (angleSlot(a).issue % ii, a))
    (0 until cordicUnits).map(u => bound.getOrElse(u, Nil).sortBy(_._1))
  }

  /** Register bits that hold values between their cycles (stage chains, see the hardware), for reports. */
  def heldBits: Long = ids.map { id =>
    val last = reads(id.index).maxOption
    (apply(id), last) match {
      case (Some(t), Some(l)) => (if (ii == 1) (l - t + 1).toLong else ((l - t) / ii + 1).toLong) * analysis(id).format.width
      case _                  => 0L
    }
  }.sum

  /** Samples per second at a clock of `hz`. */
  def samplesPerSecond(hz: Double): Double = hz / ii
}
