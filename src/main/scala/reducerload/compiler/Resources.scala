package reducerload.compiler

import reducerload.util.IntMath.ceilDiv

import reducerload.arm.{ArmDatapath, ArmParams}
import reducerload.config.{Device, DeviceFamily}
import reducerload.cordic.ResidualRotation
import reducerload.graph.{
  BankedSchedule,
  HeldTaps,
  MulShape,
  Operand,
  OperandSource,
  PlacedOp,
  ProductAlignment,
  Schedule,
  SinCosMemory,
  UnitKind
}
import reducerload.monitor.MonitorParams
import reducerload.pipeline.MemoryDelay

/**
 * A design's use of a device's resources: 18x18 multiplier blocks, memory blocks, logic cells (predicted).
 */
final case class Resources(multiplierBlocks: Int, memoryBlocks: Int, logicElements: Int) {
  def +(o: Resources): Resources =
    Resources(
      multiplierBlocks + o.multiplierBlocks,
      memoryBlocks + o.memoryBlocks,
      logicElements + o.logicElements
    )
}

/** One resource of a device, for fits and reports. */
sealed abstract class Resource(val name: String) {
  def used(r: Resources): Int
  def capacity(d: Device): Int
  def unit(d: Device): String
}
object Resource {
  case object MultiplierBlocks extends Resource("multiplier blocks") {
    def used(r: Resources): Int = r.multiplierBlocks
    def capacity(d: Device): Int = d.multiplierBlocks
    def unit(d: Device): String = "18x18 multiplier blocks"
  }
  case object MemoryBlocks extends Resource("memory blocks") {
    def used(r: Resources): Int = r.memoryBlocks
    def capacity(d: Device): Int = d.memoryBlocks
    def unit(d: Device): String = d.family.memoryBlock
  }
  case object LogicElements extends Resource("logic elements") {
    def used(r: Resources): Int = r.logicElements
    def capacity(d: Device): Int = d.logicElements
    def unit(d: Device): String = d.family.logicCell
  }
  val all: Seq[Resource] = Seq(MultiplierBlocks, MemoryBlocks, LogicElements)
}

/**
 * A memory the generator instantiates: `copies` arrays (one per read port) of `depth` words of `width` bits.
 */
final case class MemoryArray(what: String, depth: Int, width: Int, copies: Int = 1) {
  def blocks(family: DeviceFamily): Int = copies * family.blocksFor(depth, width)
}
object MemoryArray {

  /** The array of a block-RAM delay of `cycles` clocks ([[MemoryDelay]]). */
  def delay(what: String, cycles: Int, width: Int): MemoryArray =
    MemoryArray(what, MemoryDelay.depth(cycles), width)
}

/**
 * A compiled design's resources predicted without synthesis: the schedule's 18x18 blocks (exact), the memory
 * blocks of every memory the generator builds (counted from the structures that build them, in the family's
 * block shapes), and logic cells from an analytic count calibrated against the open-tool estimate (see
 * [[ResourceModel.logicElements]]).
 */
object ResourceModel {

  /**
   * The arrays of one CORDIC unit: the start-vector table ROM and the residual rotation's block-RAM delay.
   */
  private def cordicArrays(p: ArmParams): Seq[MemoryArray] = {
    val c = p.schedule.cordic
    val w = c.xyFormat.width
    (if (c.tableBits > 0) Seq(MemoryArray("CORDIC start table", 1 << c.tableBits, c.startTableVaryingBits))
     else Nil) ++
      (if (c.residual)
         Seq(MemoryArray.delay("CORDIC residual delay", ResidualRotation.stateDelayInMemory, 2 * w + 2))
       else Nil)
  }

  /**
   * A value held from `ready` to each of `reads` at II = 1: one delay line, a block-RAM delay
   * (pipeline.MemoryDelay, `MemoryDelay.depth`) for each stretch of `datapath.memory-delay-min-cycles` or
   * more, its last clock in logic (ArmDatapath.held, ArmDatapath.delayFabricRegisters).
   */
  private def heldArrays(
      p: ArmParams,
      what: String,
      width: Int,
      ready: Int,
      reads: Seq[Int]
  ): Seq[MemoryArray] =
    if (p.memoryDelayMinCycles == 0) Nil
    else {
      val taps = reads.distinct.sorted
      (ready +: taps).zip(taps).collect {
        case (t, r) if MemoryDelay.inBlockRam(r - t, p.memoryDelayMinCycles) =>
          MemoryArray.delay(what, r - t - ArmDatapath.delayFabricRegisters(p.schedule, r - t), width)
      }
    }

  /** Every memory array of the arm datapath. */
  def memories(p: ArmParams): Seq[MemoryArray] = {
    val s = p.schedule
    val cordic = Seq.fill(s.cordicUnits)(cordicArrays(p)).flatten
    val storage = p.banked match {
      case Some(b) =>
        b.banks.indices.map { bank =>
          val depth = BankedSchedule.pow2(b.values(bank).size) * b.copies(bank)
          MemoryArray(s"bank $bank", depth, b.bankWidths(bank), copies = 2)
        } :+ MemoryArray("microcode table", s.clocksPerSample, microcodeWidth(p, b))
      case None if s.clocksPerSample == 1 =>
        val g = p.graph
        val values = g.ids.flatMap { id =>
          s(id).toSeq.flatMap(ready =>
            heldArrays(p, "delay", p.analysis(id).format.width, ready, s.reads(id.index))
          )
        }
        val angles = p.chain.joints.indices.flatMap(j =>
          heldArrays(p, "angle delay", p.numerics.angleBits, 1, s.angleReads(j))
        )
        values ++ angles
      case None =>
        // registers storage at 2 clocks per sample or more: the block-RAM taps of held values (HeldTaps)
        // a delay's last clock in logic with registered routes (ArmDatapath.delayFabricRegisters); those
        // registers are not counted in the logic: they pack with the LUTs of the group multiplexers they
        // feed (the open-tool estimate did not grow with them: docs/timing-closure.md)
        def delays(what: String, width: Int, taps: HeldTaps) = taps.delayed.map { k =>
          val cycles = k * s.clocksPerSample
          MemoryArray.delay(what, cycles - ArmDatapath.delayFabricRegisters(s, cycles), width)
        }
        val g = p.graph
        val values =
          g.ids.flatMap(id => p.heldTaps(id).toSeq.flatMap(delays("delay", p.analysis(id).format.width, _)))
        val angles = p.chain.joints.indices.flatMap(j =>
          delays(
            "angle delay",
            p.numerics.angleBits,
            HeldTaps(s.clocksPerSample, 1, s.angleReads(j), p.memoryDelayMinCycles)
          )
        )
        val products = s.productMemories.map(m => MemoryArray("product memory", s.clocksPerSample, m.width))
        val sinCos =
          s.sinCosMemories.map(m => MemoryArray("sin/cos memory", SinCosMemory.depth, p.sinCosWidth(m)))
        values ++ angles ++ products ++ sinCos
    }
    cordic ++ storage
  }

  private def log2Ceil(n: Int) = if (n <= 1) 0 else 32 - Integer.numberOfLeadingZeros(n - 1)

  /** Distinct sources of port `k` of a unit running `ops` (arm.MemoryStorage.PortSources). */
  private def optionCount(b: BankedSchedule, ops: Seq[PlacedOp], k: Int, shift: (PlacedOp, Int) => Int): Int =
    ops
      .map(o =>
        (
          OperandSource.of(o.operands(k), x => b.bankOf(x).get),
          o.operands(k) match {
            case Operand.Constant(_) | Operand.Zero => 0
            case _                                  => shift(o, k)
          }
        )
      )
      .distinct
      .size

  /** Each memory-storage unit port's options times its width: the select multiplexers' inputs. */
  private def selectInputs(p: ArmParams, b: BankedSchedule): Long = {
    val a = p.analysis
    val alignment = b.alignment
    val multipliers = (0 until p.schedule.multiplierUnits).map { u =>
      val ops = b.opsOn(UnitKind.Multiplier, u)
      // the operand multiplexer, then the shift multiplexer after the operand register
      p.schedule
        .unitShape(u)
        .widths
        .zipWithIndex
        .map { case (width, k) =>
          (optionCount(b, ops, k, (_, _) => 0) + ProductAlignment.muxInputs(
            alignment.muxShifts(u, k).size
          )).toLong *
            width
        }
        .sum
    }.sum
    val adders = (0 until b.adderUnits).map { u =>
      val ops = b.opsOn(UnitKind.Adder, u)
      def shift(o: PlacedOp, k: Int) =
        o.operands(k).carried.fold(0)(x => a(o.node).format.fracBits - a(x).format.fracBits)
      (optionCount(b, ops, 0, shift) + optionCount(b, ops, 1, shift)).toLong * b.adderWidths(u)
    }.sum
    multipliers + adders
  }

  /**
   * Bits of memory storage's microcode word (arm.MemoryStorage: one word per residue): each bank's write and
   * read addresses and write enable, each unit port's select (the low bits of the option within groups of
   * four, one clear bit per group) and constant, each multiplier's product-drop select, each adder's subtract
   * flag. An upper bound: the table shares equal fields.
   */
  def microcodeWidth(p: ArmParams, b: BankedSchedule): Int = {
    val a = p.analysis
    val banks = b.banks.indices.map { bank =>
      val address = log2Ceil(BankedSchedule.pow2(b.values(bank).size)) + log2Ceil(b.copies(bank))
      3 * math.max(1, address) + 1
    }.sum
    def port(ops: Seq[PlacedOp], k: Int, shift: (PlacedOp, Int) => Int): Int = {
      val options = optionCount(b, ops, k, shift)
      val groups = (options + 3) / 4
      val constant = ops
        .collect {
          case o @ PlacedOp(_, _, _, _, ops, _) if ops(k).isInstanceOf[Operand.Constant] =>
            val Operand.Constant(x) = ops(k): @unchecked
            a(x).format.width + shift(o, k)
        }
        .maxOption
        .getOrElse(0)
      (if (options > 1) log2Ceil(math.min(options, 4)) else 0) + (if (groups > 1) groups else 0) + constant
    }
    val alignment = b.alignment
    val multipliers = (0 until p.schedule.multiplierUnits).map { u =>
      val ops = b.opsOn(UnitKind.Multiplier, u)
      def select(options: Int) = if (options > 1) log2Ceil(options) else 0
      (0 to 1)
        .map(k => port(ops, k, (o, _) => alignment(o).fromTable(k)) + select(alignment.muxShifts(u, k).size))
        .sum +
        log2Ceil(math.max(alignment.drops(u).size, 2))
    }.sum
    val adders = (0 until b.adderUnits).map { u =>
      val ops = b.opsOn(UnitKind.Adder, u)
      def shift(o: PlacedOp, k: Int) =
        o.operands(k).carried.fold(0)(x => a(o.node).format.fracBits - a(x).format.fracBits)
      port(ops, 0, shift) + port(ops, 1, shift) + 1
    }.sum
    banks + multipliers + adders
  }

  /** The monitor's arrays: each joint's power table ROM and velocity delay (MonitoredArm). */
  def monitorMemories(p: ArmParams, m: MonitorParams): Seq[MemoryArray] =
    (0 until m.joints).flatMap { j =>
      val t = m.powerTables(j)
      val delay = p.latency - ArmDatapath.inputCycle
      Seq(MemoryArray("monitor power table", t.base.size, t.baseBits + t.deltaBits + t.shiftBits)) ++
        (if (MemoryDelay.inBlockRam(delay, p.memoryDelayMinCycles))
           Seq(MemoryArray.delay("monitor velocity delay", delay, p.numerics.velocityFormats(j).width))
         else Nil)
    }

  /**
   * What the logic-cell count is made of, each in bits (the fit says how many LEs per bit): registers that
   * hold values (registers storage: at II = 1 those outside block-RAM delays, each with the adder that writes
   * it; memory storage: the microcode word's control registers); the shared multiplier units'
   * operand-multiplexer inputs beyond the first (registers storage); CORDIC stages; the adders summing a
   * multi-block product's partial products; memory storage's unit-port select inputs; its bank words (the
   * read registers of both ports). The adders' own bits follow the registers so closely over the sweep that a
   * term of their own took a negative weight: they are left to the register term.
   */
  final case class LogicFeatures(
      registerBits: Double,
      multiplexerBits: Double,
      cordicBits: Double,
      partialProductBits: Double,
      selectBits: Double,
      bankBits: Double
  ) {
    def toSeq: Seq[Double] =
      Seq(registerBits, multiplexerBits, cordicBits, partialProductBits, selectBits, bankBits)
  }

  /**
   * Register bits of the values held at II = 1 (ArmDatapath.held): a block-RAM delay counts its output
   * register and its register in logic (ArmDatapath.delayFabricRegisters).
   */
  private def registerBitsAtOne(p: ArmParams): Long = {
    val s = p.schedule
    def line(width: Int, ready: Int, reads: Seq[Int]): Long = {
      val taps = reads.distinct.sorted
      (ready +: taps)
        .zip(taps)
        .map { case (t, r) =>
          if (MemoryDelay.inBlockRam(r - t, p.memoryDelayMinCycles))
            1L + ArmDatapath.delayFabricRegisters(s, r - t)
          else (r - t).toLong
        }
        .sum * width
    }
    p.graph.ids
      .flatMap(id => s(id).map(ready => line(p.analysis(id).format.width, ready, s.reads(id.index))))
      .sum +
      p.chain.joints.indices.map(j => line(p.numerics.angleBits, 1, s.angleReads(j))).sum
  }

  /**
   * Register bits registered routes add (ArmDatapath, `datapath.registered-routes`): per unit port a register
   * per group of sources and the operand register with their select copies, per held register its enable's
   * copy (and the first-level copies). Not calibrated: counted as held bits, which is high where a register
   * packs with the multiplexer that feeds it.
   */
  private def routeRegisterBits(p: ArmParams, units: IndexedSeq[MulShape]): Double = {
    val s = p.schedule
    val operands = s.mulBindings.indices.map { u =>
      val ports = s.portSources(u).zip(units(u).widths).map { case (sources, w) =>
        val groups = ArmDatapath.routeGroups(sources)
        (groups.size + 1) * w + (groups.map(_.size) :+ groups.size).map(ArmDatapath.groupSelectBits(w, _)).sum
      }
      ports.sum
    }.sum
    (operands + p.heldRegisters + ceilDiv(p.heldRegisters, ArmDatapath.enableFanout)).toDouble
  }

  def features(p: ArmParams): LogicFeatures = {
    val s: Schedule = p.schedule
    val c = p.schedule.cordic
    val stageBits = 2 * c.xyFormat.width + c.zFracBits
    val cordicBits = s.cordicUnits.toDouble * stageBits *
      (c.iterations - c.firstIteration + 2 + c.tableRouteRegisters)
    val units = (0 until s.multiplierUnits).map(s.unitShape)
    val partial = units.map(u => (u.blocks - 1) * (u.wide + u.narrow - 18)).sum.toDouble
    val operandBits =
      if (s.dedicated) 0.0
      else
        s.mulBindings.indices
          .map(u =>
            s.portSources(u)
              .zip(units(u).widths)
              .map { case (sources, w) => math.max(0, sources.size - 1) * w }
              .sum
          )
          .sum
          .toDouble
    p.banked match {
      case None =>
        LogicFeatures(
          if (s.dedicated) registerBitsAtOne(p).toDouble
          else p.heldRegisterBits.toDouble + (if (s.routed) routeRegisterBits(p, units) else 0.0),
          operandBits,
          cordicBits,
          partial,
          0,
          0
        )
      case Some(b) =>
        LogicFeatures(
          microcodeWidth(p, b).toDouble,
          0,
          cordicBits,
          partial,
          selectInputs(p, b).toDouble,
          b.banks.indices.map(k => 2.0 * b.bankWidths(k)).sum
        )
    }
  }

  /**
   * LEs per bit of each feature and the fixed logic (input clamps, output stage, control), fitted by least
   * squares of the relative error to the open-tool Cyclone IV estimate (est_les) of the 90 points committed
   * in docs/sweep/arms.csv and sweep.csv (ResourceFit; the held and multiplexer bits' weights are the
   * refinement's, held at theirs, the rest refitted 2026-12-07 after the estimate's block-RAM registers were
   * counted right). ResourceModelSpec checks every committed point against the tolerance and prints the table
   * of docs/device.md. An operand-multiplexer input costs about an LE per bit since each is a distinct
   * register (before the binding, 0.47: repeated inputs were merged by synthesis).
   */
  val coefficients: Seq[Double] =
    Seq(reducerload.graph.LogicCost.heldBit, reducerload.graph.LogicCost.muxBit, 0.916, 1.146, 0.645, 4.435)
  val fixedLogic: Double = 717.4

  /** The prediction's tolerance against the open-tool estimate over the committed points (see above). */
  val logicTolerance: Double = 0.21

  /** Predicted logic cells of the arm datapath. */
  def logicElements(p: ArmParams): Int =
    math.round(fixedLogic + features(p).toSeq.zip(coefficients).map { case (f, k) => f * k }.sum).toInt

  /**
   * Predicted logic cells of a monitor: its live and shadow state (each value's bits twice; the update logic
   * packs with the live registers) and the read-out multiplexer over the 32-bit words (about a third of an LE
   * per input bit). Not calibrated: no monitored design has a committed estimate.
   */
  def monitorLogicElements(m: MonitorParams): Int =
    2 * m.registerMap.entries.map(_.width).sum + 11 * m.registerMap.words

  /** The arm datapath's resources on `family`. */
  def of(p: ArmParams, family: DeviceFamily): Resources =
    Resources(
      p.schedule.multiplierBlocks,
      memories(p).map(_.blocks(family)).sum,
      logicElements(p)
    )

  /** A monitor's resources on `family`, beside the arm `p`. */
  def ofMonitor(p: ArmParams, m: MonitorParams, family: DeviceFamily): Resources =
    Resources(
      (0 until m.joints).map(m.multiplierBlocks).sum,
      monitorMemories(p, m).map(_.blocks(family)).sum,
      monitorLogicElements(m)
    )
}
