package reducerload.arm

import chisel3._
import chisel3.util._
import reducerload.cordic.SinCos
import reducerload.fixedpoint.FixedHw
import reducerload.graph._
import reducerload.pipeline.{MultiplierImpl, PipelinedMultiplier}

/**
 * The memory-storage body of [[ArmDatapath]] (`schedule.storage = memory`): the hardware of a
 * [[BankedSchedule]]. Every unit (the input stage, each multiplier, adder and CORDIC unit) writes its result
 * into the unit's bank through one register ([[BankedSchedule.writeDelay]]); units read their operands from
 * the banks' two read ports (port 0 for first operands, port 1 for second), through a multiplexer over the
 * banks that port actually reads. What each bank port, multiplexer, shift and unit does in a cycle comes from
 * one table indexed by the phase (a ROM of II words, [[Microcode]]), so no value has a register or
 * multiplexer input of its own.
 *
 * Called while [[ArmDatapath]] elaborates: `signals` are the clamped inputs (valid in `inputCycle` only),
 * `cordic` the CORDIC units' outputs, `during(c)` is true in cycle c of every sample, and `residueCounter(r)`
 * is a new counter of residues modulo II, at `r` in the cycle after reset (the datapath's phase is such a
 * counter at 0). The result is each output node's value, held until `outputsReady`.
 */
final class MemoryStorage(
    p: ArmParams,
    b: BankedSchedule,
    residueCounter: Int => UInt,
    during: Int => Bool,
    held: (SInt, Int, Seq[Int]) => Map[Int, SInt],
    signals: Signal => SInt,
    cordic: IndexedSeq[SinCos]
)(implicit multiplierImpl: MultiplierImpl) {
  import Op._
  private val analysis = p.analysis
  private val graph = p.graph
  private val ii = b.clocksPerSample
  private def residue(cycle: Int) = Math.floorMod(cycle, ii)

  /** A field's values a cycle early, for a register after the table's. */
  private def earlier(f: Field) = Field(f.width, f.values.map { case (r, v) => residue(r - 1) -> v })
  private def fmt(x: NodeId) = analysis(x).format

  // ---- The table: every control field, by residue, as plain integers first. ----

  /** Slot counter: which of a bank's copies the sample of the current cycle 0 uses. */
  private val tagBits = log2Ceil(b.slotCount)
  private val slotCounter: UInt =
    if (tagBits == 0) 0.U(1.W)
    else {
      val c = RegInit(0.U(tagBits.W))
      when(during(ii - 1))(c := c + 1.U) // wraps modulo slotCount, a power of 2
      c
    }

  /** A bank's addresses: a value's slot below, the copy of its sample above. */
  private final class BankAddressing(bank: Int) {
    val slotBits: Int = log2Ceil(BankedSchedule.pow2(b.values(bank).size))
    val copyBits: Int = log2Ceil(b.copies(bank))
    val depth: Int = 1 << (slotBits + copyBits)
    val width: Int = math.max(1, slotBits + copyBits)

    /**
     * The table entry of an access to `node` in `cycle`: its slot, and the whole intervals since its sample's
     * cycle 0.
     */
    def entry(node: NodeId, cycle: Int): BigInt =
      (BigInt(b.intervalsBefore(cycle) % b.copies(bank)) << slotBits) | b.slot(node)

    /** The address from an entry: the copy is the slot counter less the intervals (modulo the copies). */
    def address(entry: UInt): UInt = {
      val copy =
        if (copyBits == 0) None
        else Some((slotCounter - entry(slotBits + copyBits - 1, slotBits))(copyBits - 1, 0))
      val slot = if (slotBits == 0) None else Some(entry(slotBits - 1, 0))
      (copy.toSeq ++ slot.toSeq).reduceOption(Cat(_, _)).getOrElse(0.U(1.W))
    }
    // A value leaves its unit in the cycle before it is ready; the table addresses its write then (registered
    // with the data).
    val write: Field =
      Field(width, b.values(bank).map(v => residue(b.ready(v).get - 1) -> entry(v, b.ready(v).get - 1)).toMap)
    val writeEnable: Field = Field.flag(b.values(bank).map(v => residue(b.ready(v).get - 1)).toSet)
    val reads: IndexedSeq[Field] = (0 to 1).map(port =>
      Field(
        width,
        b.reads
          .filter(r => r.bank == bank && r.port == port)
          .map(r => residue(r.cycle) -> entry(r.node, r.cycle))
          .toMap
      )
    )
  }
  private val addressing = b.banks.indices.map(new BankAddressing(_))

  /**
   * A unit port's sources (`operands` by the residue of the cycle their selection starts, each with the bits
   * it is shifted left by: an addition aligns its operands' fraction bits here, in the wiring of the first
   * stage's inputs, so no stage of its own does): the banks it reads (once per shift), then a constant (or
   * zero) if any. The selection takes `b.selectStages` clocks (two, or one at a tight interval): in the
   * first, each group of [[MemoryStorage.selectGroup]] options picks by the low bits of the option's index
   * (the same bits for every group, each from its own copy of the select) and is registered, cleared unless
   * its group holds the option (one clear bit per group, set for the other groups, so that it drives the
   * registers' synchronous reset with no inverter between); in the second, the groups are ORed. A port with
   * 30 options then has eight 4-way multiplexers in one clock and an 8-input OR in the next instead of a
   * 32-way multiplexer in one, and the second clock needs no select (a select register driving every bit of a
   * wide multiplexer reaches across the chip).
   */
  private final class PortSources(operands: Seq[Selection]) {

    /** An operand's option: the table's constant field holds each constant shifted already. */
    private def optionOf(o: Operand, shift: Int): MuxInput = OperandSource.of(o, x => b.bankOf(x).get) match {
      case OperandSource.Table => MuxInput(OperandSource.Table, 0)
      case source              => MuxInput(source, shift)
    }

    /**
     * Options, in [[MuxInput.ordering]]: the bank read ports, the output registers, then the table if any.
     */
    val sources: IndexedSeq[MuxInput] =
      operands.map(o => optionOf(o.operand, o.shift)).distinct.sorted.toIndexedSeq
    // The table holds each constant shifted already.
    private val constants: Map[Int, (BigInt, Int)] = operands.collect {
      case Selection(r, Operand.Constant(x), shift) =>
        r -> (analysis(x).raw.get << shift, fmt(x).width + shift)
      case Selection(r, Operand.Zero, _) => r -> (BigInt(0), 1)
    }.toMap
    private val constantWidth = constants.values.map(_._2).maxOption.getOrElse(1)
    private val index: Seq[(Int, Int)] =
      operands.map(o => o.residue -> sources.indexOf(optionOf(o.operand, o.shift)))
    private val options: Int = sources.size
    private val group = MemoryStorage.selectGroup
    private val groups: Int = (options + group - 1) / group

    /** The index within its group, in the first stage's cycle (None: one option). */
    val selectLow: Option[Field] =
      if (options <= 1) None
      else
        Some(
          Field(log2Ceil(math.min(options, group)), index.map { case (r, i) => r -> BigInt(i % group) }.toMap)
        )

    /**
     * One clear bit per group, set for every group but the option's, in the first stage's cycle (None: one
     * group).
     */
    val groupClears: Option[Field] =
      if (groups <= 1) None
      else
        Some(
          Field(
            groups,
            index.map { case (r, i) => r -> (((BigInt(1) << groups) - 1) ^ (BigInt(1) << (i / group))) }.toMap
          )
        )

    /** Two's complement codes of the constants, in the constant field's width. */
    val constant: Option[Field] =
      if (constants.isEmpty) None
      else
        Some(
          Field(
            constantWidth,
            constants.map { case (r, (c, _)) => r -> (c & ((BigInt(1) << constantWidth) - 1)) }
          )
        )

    /**
     * The selects come from registers after the table's word ([[control]]): the table holds them a cycle
     * early.
     */
    def fields: Seq[Field] = selectLow.map(earlier).toSeq ++ groupClears.map(earlier).toSeq ++ constant.toSeq
  }

  private val alignment = b.alignment

  /** Which of `options` each of `ops` takes, in the residue `at` gives: a select field. */
  private def selectField(
      ops: Seq[PlacedOp],
      options: IndexedSeq[Int],
      at: PlacedOp => Int,
      of: PlacedOp => Int
  ) =
    Field(
      log2Ceil(math.max(options.size, 2)),
      ops.map(o => residue(at(o)) -> BigInt(options.indexOf(of(o)))).toMap
    )

  /**
   * A multiplier unit: sources the cycle before the issue (operands registered, a constant shifted in the
   * table), each operand's shift in the issue's cycle ([[ProductAlignment]]), each product's dropped bits the
   * cycle before it is ready. Both selects come from registers after the table's word ([[control]]: straight
   * from the table's word the rounding select's route to the rounding multiplexer ahead of the bank's write
   * register limited the Z1 at 88 clocks per sample, docs/timing-closure.md).
   */
  private final class MultiplierPlan(u: Int) {
    private val ops = b.opsOn(UnitKind.Multiplier, u)
    val ports: IndexedSeq[PortSources] = (0 to 1).map(port =>
      new PortSources(
        ops.map(o =>
          Selection(residue(o.issue - b.forwardLead), o.operands(port), alignment(o).fromTable(port))
        )
      )
    )
    val shifts: IndexedSeq[IndexedSeq[Int]] = (0 to 1).map(alignment.muxShifts(u, _))
    val shiftSelects: IndexedSeq[Field] =
      (0 to 1).map(port => selectField(ops, shifts(port), _.issue, alignment(_).muxShifts(port)))
    val drops: IndexedSeq[Int] = alignment.drops(u)
    val dropSelect: Field = selectField(ops, drops, o => b.ready(o.node).get - 1, alignment(_).drop)
    def fields: Seq[Field] =
      ports.flatMap(_.fields) ++ (0 to 1).filter(shifts(_).size > 1).map(p => earlier(shiftSelects(p))) :+
        earlier(dropSelect)
  }
  private val multipliers = (0 until p.schedule.multiplierUnits).map(new MultiplierPlan(_))

  /**
   * An adder unit: sources (aligned) `forwardLead` cycles before the issue, add or subtract one cycle before
   * (each step registered).
   */
  private final class AdderPlan(u: Int) {
    private val ops = b.opsOn(UnitKind.Adder, u)

    /**
     * Fraction bits an operand gains to reach its sum's (the analysis's rule for exact sums); zero needs
     * none.
     */
    private def shift(o: PlacedOp, port: Int) =
      o.operands(port).carried.fold(0)(x => fmt(o.node).fracBits - fmt(x).fracBits)
    val ports: IndexedSeq[PortSources] = (0 to 1).map(port =>
      new PortSources(
        ops.map(o => Selection(residue(o.issue - b.forwardLead), o.operands(port), shift(o, port)))
      )
    )
    val subtract: Field = Field.flag(ops.filter(_.subtract).map(o => residue(o.issue - 1)).toSet)

    /**
     * Add or subtract comes from a register after the table's word ([[control]]): the table holds it a cycle
     * early.
     */
    def fields: Seq[Field] = ports.flatMap(_.fields) :+ earlier(subtract)
  }
  private val adders = (0 until b.adderUnits).map(new AdderPlan(_))

  // ---- Hardware. ----
  require(
    Microcode.ahead <= p.schedule.inputCycle + BankedSchedule.inputLatency - 1,
    s"MemoryStorage: the table's first word comes ${Microcode.ahead} cycles after " +
      s"reset, after a sample's first write"
  )
  private val word = new Microcode(
    ii,
    addressing.flatMap(a => Seq(a.write, a.writeEnable) ++ a.reads) ++ multipliers.flatMap(_.fields) ++
      adders.flatMap(_.fields),
    residueCounter(0)
  )

  private def bankIndex(bank: Bank) = b.banks.indexOf(bank)

  /**
   * A control field in the cycle of its use, from a register of its own after the table's word (the table
   * holds it a cycle early), which the placer can put near the unit it drives. One register, not a copy per
   * slice of the unit: synthesis merges such copies back into one.
   */
  private def control(f: Field): UInt = FixedHw.delay(word(earlier(f)), 1)
  private def fit(v: SInt, width: Int): SInt = FixedHw.fitWidth(v, width)

  /** `v` shifted left by `shift` bits in `width` bits (the schedule leaves the shifted value room there). */
  private def shiftedIn(v: SInt, shift: Int, width: Int): SInt = (fit(v, width) << shift)(width - 1, 0).asSInt

  /**
   * Each unit's result, written into its bank (block RAM registers its write port), and its output register
   * (forwarding).
   */
  private val next: IndexedSeq[SInt] = b.banks.indices.map(bank => Wire(SInt(b.unitWidths(bank).W)))
  private val out: IndexedSeq[SInt] = next.map(FixedHw.delay(_, 1))

  /**
   * Each bank's two read ports: the word a cycle before it is in the registers of the unit ports that take it
   * (`readLatency` cycles after its address, [[operand]]). The address is registered, read, and the word
   * registered twice. Yosys maps the address register to the fabric, the first word register to the block
   * RAM's synchronous read and the second to its output register, whose pin then drives the third, in the
   * fabric, that the unit ports select from: the route from the block RAM, which may sit far from the units,
   * has a clock with no logic in it.
   *
   * The word is registered after the read (read-first), not read at a registered address (write-first): the
   * schedule never reads a word in the cycle it is written (a value is read after it is ready, and
   * overwritten only after the last cycle its array is read, see [[BankedSchedule.copies]]), so either order
   * gives the same words. Synthesis must still honour whatever order the RTL states for such a collision, and
   * the RAM blocks serve neither across their ports, so it would add a bypass after the RAM output. The read
   * is therefore enabled only when it does not collide (a disabled read returns an undefined word): Yosys
   * recognizes that as "don't care on collision" and maps the bare RAM.
   */
  private val readData: IndexedSeq[IndexedSeq[SInt]] = b.banks.indices.map { bank =>
    val a = addressing(bank)
    // The write, registered (BankedSchedule.writeDelay): the route from a unit to its bank's block RAM gets a
    // clock of its own.
    val writeAddress = FixedHw.delay(a.address(word(a.write)), BankedSchedule.writeDelay)
    val writeEnable = FixedHw.delay(word(a.writeEnable).asBool, BankedSchedule.writeDelay)
    val writeData = FixedHw.delay(fit(next(bank), b.bankWidths(bank)).asUInt, BankedSchedule.writeDelay)
    (0 to 1).map { port =>
      val mem = Mem(a.depth, UInt(b.bankWidths(bank).W))
      when(writeEnable)(mem.write(writeAddress, writeData))
      val address = FixedHw.delay(a.address(word(a.reads(port))), BankedSchedule.arrayReadDelay)
      val data = Wire(UInt(b.bankWidths(bank).W))
      data := DontCare
      when(!(writeEnable && writeAddress === address))(data := mem.read(address))
      FixedHw.delay(data, BankedSchedule.readLatency - BankedSchedule.arrayReadDelay).asSInt
    }
  }

  /**
   * A unit port's operand, selected from the options of the cycle its selection starts and out of the
   * multiplexer `b.selectStages` - 1 cycles later (to be registered by the unit), sign-extended or cut to
   * `width` (values fit their formats).
   */
  private def operand(src: PortSources, width: Int): SInt = {
    val options = src.sources.map {
      case MuxInput(OperandSource.ReadPort(bank, port), shift) =>
        shiftedIn(readData(bank)(port), shift, width)
      case MuxInput(OperandSource.Output(bank), shift) => shiftedIn(out(bank), shift, width)
      case MuxInput(OperandSource.Table, _)            => fit(word(src.constant.get).asSInt, width)
    }
    // Each group its own copy of the low select bits, kept (synthesis would merge the copies): one register
    // for every group reaches across the chip to the far ones (docs/timing-closure.md, the xArm7).
    def low = FixedHw.kept(control(src.selectLow.get))
    lazy val clears = control(src.groupClears.get)
    // A unit the schedule left idle (more adder units asked for than it used) has no options.
    val grouped =
      if (options.isEmpty) Seq(Seq(0.S(width.W))) else options.grouped(MemoryStorage.selectGroup).toSeq
    val groups = grouped.zipWithIndex.map { case (g, k) =>
      val picked = if (g.size == 1) g.head else VecInit(g)(low(log2Ceil(g.size) - 1, 0))
      FixedHw.delay(if (grouped.size == 1) picked else Mux(clears(k), 0.S, picked), b.selectStages - 1)
    }
    groups.reduce((x, y) => (x.asUInt | y.asUInt).asSInt)
  }

  // Inputs: all loaded into a chain of registers in the input cycle (the only cycle the clamped
  // values are there: their registers take the port every clock), behind `inputLoadDelay` places
  // that shift on (they still hold the sample before's last inputs at an interval as short as the
  // inputs are many), then written one per clock from its head as the chain shifts
  // ([[BankedSchedule.inputLatency]]): no select from the table (a wide multiplexer ahead of the
  // bank's write port).
  if (b.signals.nonEmpty) {
    val width = b.unitWidth(Bank.Inputs)
    val values = b.signals.map(signals(_).pad(width))
    val ahead = BankedSchedule.inputLoadDelay
    val chain = Reg(Vec(ahead + values.size, SInt(width.W)))
    chain.init.zip(chain.tail).foreach { case (r, later) => r := later }
    when(during(p.schedule.inputCycle)) {
      values.zipWithIndex.foreach { case (v, k) => chain(ahead + k) := v }
    }
    next(bankIndex(Bank.Inputs)) := chain.head
  }

  // Multiplier units.
  multipliers.zipWithIndex.foreach { case (plan, u) =>
    val shape = p.schedule.unitShape(u)
    // Operands registered in the fabric (the selection's long routes to the multiplier blocks get a clock of
    // their own), then shifted on the way to the blocks' own input registers.
    val operands = shape.widths.zipWithIndex.map { case (width, port) =>
      val registered = FixedHw.delay(operand(plan.ports(port), width), 1)
      val shifted = plan.shifts(port).map(shiftedIn(registered, _, width))
      if (shifted.size == 1) shifted.head else VecInit(shifted)(control(plan.shiftSelects(port)))
    }
    val product = FixedHw.delay(PipelinedMultiplier(operands(0), operands(1)), p.multiplierLatency - 1)
    val width = b.unitWidth(Bank.Products(u))
    val rounded = plan.drops.map(d => fit(FixedHw.shiftRound(product, d, p.productRounding), width))
    next(bankIndex(Bank.Products(u))) := (if (rounded.size == 1) rounded.head
                                          else VecInit(rounded)(control(plan.dropSelect)))
  }

  // Adder units.
  adders.zipWithIndex.foreach { case (plan, u) =>
    val width = b.adderWidths(u)
    val subtract = control(plan.subtract).asBool
    val aligned = (0 to 1).map(port => operand(plan.ports(port), width).asUInt)
    // a - b as a + ~b + 1 (FixedHw.addSub's form), with ~b (in the select's last LUT) and the carry
    // in registered beside a: the table's subtract bit then drives no logic ahead of the carry chain.
    val a = FixedHw.delay(aligned(0), 1)
    val bFlipped = FixedHw.delay(aligned(1) ^ Fill(width, subtract), 1)
    val carryIn = FixedHw.delay(subtract.asUInt, 1)
    val sum = (Cat(a, 1.U(1.W)) + Cat(bFlipped, carryIn))(width, 1).asSInt
    next(bankIndex(Bank.Sums(u))) := fit(sum, b.unitWidth(Bank.Sums(u)))
  }

  // CORDIC units.
  cordic.zipWithIndex.foreach { case (sc, u) =>
    Seq(TrigFn.Cos -> sc.cos, TrigFn.Sin -> sc.sin).foreach { case (fn, v) =>
      val bank = bankIndex(Bank.Trig(u, fn))
      next(bank) := v.pad(b.unitWidths(bank))
    }
  }

  /**
   * Each output's value in cycle `outputsReady`: its unit's output register in the cycle it is ready, copied
   * from there and held if that is earlier: not captured from the unit's sum beside the output register,
   * which would add the route to the output stage to the adder's carry chain.
   */
  val outputs: IndexedSeq[SInt] = graph.outputs.map { o =>
    graph(o.node) match {
      case Const(_) => analysis(o.node).raw.get.S(fmt(o.node).width.W)
      case _ =>
        val ready = b.ready(o.node).get
        val value = fit(out(b.bankOf(o.node).get), fmt(o.node).width)
        if (ready == b.outputsReady) value
        else held(RegEnable(value, during(ready)), ready + 1, Seq(b.outputsReady))(b.outputsReady)
    }
  }
}

/** A control field: `width` bits with a value for some residues (the others read 0, a don't-care). */
final case class Field(width: Int, values: Map[Int, BigInt]) {
  require(width >= 1, s"Field: $width bits")
  values.foreach { case (r, v) =>
    require(v >= 0 && v.bitLength <= width, s"Field: $v does not fit $width bits at residue $r")
  }
}
object Field {

  /** A one-bit field set at `residues`. */
  def flag(residues: Set[Int]): Field = Field(1, residues.map(_ -> BigInt(1)).toMap)
}

/**
 * Control fields packed into one ROM word per residue, read [[Microcode.ahead]] cycles ahead at `address`, a
 * counter of its own that equals the phase (so the phase counter does not also drive the ROM's address pins
 * across the chip). Equal fields share their bits.
 */
final class Microcode(ii: Int, fields: Seq[Field], address: UInt) {
  private val distinct = fields.distinct
  distinct.foreach(f =>
    require(f.values.keys.forall(r => r >= 0 && r < ii), s"Microcode: a residue outside 0..${ii - 1}")
  )
  private val offsets: Map[Field, Int] = distinct.zip(distinct.map(_.width).scanLeft(0)(_ + _)).toMap
  val width: Int = distinct.map(_.width).sum

  /**
   * The word of the current residue, from registers: the ROM holds each residue's word [[Microcode.ahead]]
   * residues earlier and is read at the phase that many cycles ahead, through three registers (the block
   * RAM's address and output registers, then one in the fabric), so every control signal leaves a flip-flop
   * the placer can put near its loads, not a block-RAM read or the block RAM's own output register (the
   * word's bits fan out to every unit from one place, the block RAM). In the first `ahead` cycles after reset
   * the registers hold no word; every action of those cycles belongs to samples taken before the reset (a
   * sample's first action, its input bank's first write, comes `ahead` cycles after it is taken).
   */
  private val bits: UInt = {
    val words = (0 until ii).map(r =>
      distinct.foldLeft(BigInt(0))((acc, f) => acc | (f.values.getOrElse(r, BigInt(0)) << offsets(f)))
    )
    val rom = VecInit((0 until ii).map(r => words((r + Microcode.ahead) % ii).U(math.max(width, 1).W)))
    FixedHw.delay(rom(address), Microcode.ahead)
  }

  /** A field's bits in the current cycle. */
  def apply(f: Field): UInt = bits(offsets(f) + f.width - 1, offsets(f))
}

/**
 * An operand a unit port takes: its selection starts at `residue` of the phase, and it is shifted left by
 * `shift` bits.
 */
private final case class Selection(residue: Int, operand: Operand, shift: Int)

/**
 * One input of a unit port's operand multiplexer: its source and the bits it is shifted left by (an addition
 * aligns its operands there).
 */
final case class MuxInput(source: OperandSource, shift: Int)
object MuxInput {

  /**
   * By source ([[OperandSource.ordering]]), then by shift as decimal text: the order of the emitted
   * multiplexer's inputs (the table's constant, shifted in the table, last).
   */
  implicit val ordering: Ordering[MuxInput] =
    Ordering.by((i: MuxInput) => (i.source, i.shift))(
      Ordering.Tuple2(OperandSource.ordering, OperandSource.decimalTextOrder)
    )
}

object MemoryStorage {

  /**
   * Options a unit port selects among in the first select stage, per group: a 4-way multiplexer is one LUT
   * level on ECP5 (two LUTs and a PFUMX).
   */
  val selectGroup: Int = 4
}

object Microcode {

  /** Cycles the table is read ahead: block RAM registers its address, then its output, then the fabric. */
  val ahead: Int = 3
}
