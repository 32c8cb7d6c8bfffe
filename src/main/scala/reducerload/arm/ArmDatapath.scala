package reducerload.arm

import chisel3._
import chisel3.util._
import reducerload.cordic.CordicSinCos
import reducerload.fixedpoint.{Clamped, FixedFormat, FixedHw, Rounding}
import reducerload.graph._
import reducerload.pipeline.{
  DelayPointer,
  MemoryDelay,
  MultiplierImpl,
  PipelinedMultiplier,
  ShiftAddMultiplier
}

/**
 * Every joint torque of a serial arm: the hardware interpretation of the graph in `p.graph` at the cycles and
 * on the units of `p.schedule`. A sample is taken on `io.in` when `ready` is high (every `II =
 * p.schedule.clocksPerSample` clocks; always at II = 1) and its torques leave on `io.out` exactly `p.latency`
 * cycles later.
 *
 * A counter gives the cycle of the sample that entered last, modulo II (the phase); a shared unit's operand
 * multiplexers select by it, and every value is written once per sample, at the phase of the cycle it is
 * computed in. A value read k cycles after it is ready passes through floor(k / II) more registers written at
 * the same phase (at II = 1: a delay line, long ones in block RAM).
 *
 * In cycle 1 the angles are in the input register, and each velocity and acceleration, clamped to its joint's
 * declared range (flagging the joint), in its own (with memory storage in that cycle only). Data registers
 * have no reset; the valid chain and the phase do.
 */
class ArmDatapath(val p: ArmParams)(implicit multiplierImpl: MultiplierImpl) extends Module {
  private val schedule = p.schedule
  private val ii = schedule.clocksPerSample
  override def desiredName = p.moduleName
  val io = IO(new ArmIO(p))
  import Op._
  private val analysis = p.analysis
  private val numerics = p.numerics
  private val graph = p.graph
  private val joints = p.chain.size

  /**
   * A register counting residues modulo II, at `start` in the cycle after reset. Each group of loads (the
   * phase flags, the table's address, a registered select) has a counter of its own: one counter read by all
   * of them fans out across the chip, and its route back to its own increment limits the clock.
   */
  private def residueCounter(start: Int): UInt = {
    val counter = RegInit((start % ii).U(log2Ceil(ii).W))
    counter := Mux(counter === (ii - 1).U, 0.U, counter + 1.U)
    counter
  }

  private lazy val phase: UInt = if (ii == 1) 0.U else residueCounter(0)

  /**
   * One flip-flop per residue, high while the phase equals it, so the enables of the many registers written
   * at one phase leave a flip-flop, not a comparator (a compare driving that fan-out limits the clock).
   * Registers storage compares the phase with the residue before, a cycle early (the compare does not wait
   * for the counter's increment; residues nothing uses are removed). Memory storage and registered routes at
   * up to [[ArmDatapath.ringMaxInterval]] clocks pass one token around a ring of II flip-flops instead: no
   * counter, so no compare shared between the counter's wrap and the flag of residue 0, which the placer
   * would pull between the counter and that flag's loads. With registered routes the ring is kept: a
   * first-level enable copy ([[enable]]) is the same flip-flop as the ring's next, so synthesis merged them,
   * and the flag the selects' partial ORs read then sat beside sixteen held registers across the chip.
   */
  private val phaseIs: IndexedSeq[Bool] =
    if (ii == 1) IndexedSeq(true.B)
    else if ((p.banked.isDefined || schedule.routed) && ii <= ArmDatapath.ringMaxInterval) {
      val ring = (0 until ii).map(r => RegInit((r == 0).B))
      ring.indices.foreach(r => ring(r) := ring((r + ii - 1) % ii))
      if (schedule.routed) ring.foreach(FixedHw.kept(_))
      ring
    } else (0 until ii).map(r => RegNext(phase === ((r + ii - 1) % ii).U, (r == 0).B))

  /**
   * The entry of the current phase: a multiplexer tree indexed by the phase. Residues no operation uses
   * repeat the entry before them (any value would do; a repeat lets synthesis merge inputs).
   */
  private def byPhase[T <: Data](entries: Seq[(Int, T)]): T =
    if (entries.size == 1) entries.head._2
    else {
      val table = entries.toMap
      val first = entries.minBy(_._1)._2
      val filled = (0 until ii)
        .scanLeft(Option.empty[T])((prev, r) => table.get(r).orElse(prev))
        .tail
        .map(_.getOrElse(first))
      VecInit(filled)(phase)
    }

  /**
   * The entry of the current phase through a multiplexer whose select is a register: which entry is looked up
   * from a counter [[selectAhead]] cycles ahead of the phase, so the lookup sits between flip-flops of its
   * own and the select's routes to the multiplexer are register-to-register hops. For a select that reaches
   * far (a CORDIC unit's input among the angle sums: a select decoded from the phase, even a cycle early,
   * keeps the decode on the route). The lookup is a ROM with its read and output registers, then a register
   * in the fabric, then a kept copy of the select per [[ArmDatapath.selectSliceBits]] bits of the entries,
   * beside its slice of the multiplexer. The select is right from the first cycle after reset (registered
   * routes issue angles from cycle 1).
   */
  private def byPhaseRegistered(entries: Seq[(Int, UInt)]): UInt =
    if (entries.size == 1) entries.head._2
    else {
      val sorted = entries.sortBy(_._1)
      // The index of the entry at each residue; residues nothing uses repeat the one before.
      val index = (0 until ii).map(r => sorted.lastIndexWhere(_._1 <= r).max(0))
      val bits = log2Ceil(sorted.size)
      def at(residue: Int) = index(residue % ii).U(bits.W)
      // No reset on the lookup's registers: synthesis makes the lookup a block-RAM ROM and the registers its
      // read and output registers (with a reset the output register stays in the fabric and the ROM is read
      // bare, most of a clock). A fabric register after them takes the index a cycle later, since the ROM's
      // output crossed the die to the multiplexer. That register feeds the copies and nothing else: copies fed
      // by the ROM's output register stopped synthesis from absorbing it into the block RAM, and one select
      // decoded for every bit of the CORDIC input crossed the chip (docs/timing-closure.md, "the CORDIC select
      // copied per 8 bits").
      val read = FixedHw.delay(VecInit(index.map(_.U(bits.W)))(residueCounter(selectAhead)), romRegisters)
      // While the ROM's registers fill (a flag set by reset), registers set by reset give the indices they
      // would hold: the k-th after `at(selectAhead - 1)` set to that of residue `selectAhead - k`.
      val filling = (1 to romRegisters).foldLeft(false.B)((v, _) => RegNext(v, true.B))
      val early = (1 to romRegisters).foldLeft(at(selectAhead - 1))((r, k) => RegNext(r, at(selectAhead - k)))
      val hop = RegNext(Mux(filling, early, read), at(1))
      val width = sorted.map(_._2.getWidth).max
      Cat((0 until width).grouped(ArmDatapath.selectSliceBits).toSeq.reverse.map { slice =>
        val select = FixedHw.kept(RegNext(hop, at(0)))
        VecInit(sorted.map(_._2.pad(width)(slice.last, slice.head)))(select)
      })
    }

  /**
   * A shared unit's operand in each phase, multiplexed among its distinct `sources` (Schedule.portSources:
   * operations that read one register share an input, and [[BindingProblem]] binds them to one unit so);
   * `entries` give each residue's source and its value. The select is a register loaded in the cycle before
   * with the next phase's source, decoded from the phase flags: the decode is off the multiplexer's path. It
   * resets to residue 0's source, the phase of the first cycle after reset.
   */
  private def bySource(sources: Seq[PortSource], entries: Seq[(Int, PortSource, SInt)]): SInt =
    if (sources.size == 1) entries.head._3
    else {
      val (inputs, index) = sourcesByResidue(sources, entries)
      // each select bit: the OR of the phase flags of the residues before those that set it (a table indexed
      // by the phase would be a ROM, and a block RAM each for the open-tool estimate)
      val w = log2Ceil(sources.size)
      val next =
        (0 until w).map(b => (0 until ii).filter(r => (index((r + 1) % ii) >> b & 1) == 1).map(phaseIs))
      val select = RegInit(index(0).U(w.W))
      select := VecInit(next.map(rs => if (rs.isEmpty) false.B else rs.reduce(_ || _))).asUInt
      VecInit(inputs)(select)
    }

  /**
   * A unit port's input per source (`entries`: each residue's source and its value) and the index of the
   * source read in each residue; residues nothing reads repeat the source before them (as byPhase).
   */
  private def sourcesByResidue(
      sources: Seq[PortSource],
      entries: Seq[(Int, PortSource, SInt)]
  ): (Seq[SInt], IndexedSeq[Int]) = {
    val inputs = sources.map(src => entries.find(_._2 == src).get._3)
    val read = entries.map { case (r, src, _) => r -> sources.indexOf(src) }.toMap
    (inputs, (0 until ii).scanLeft(read(entries.map(_._1).min))((prev, r) => read.getOrElse(r, prev)).tail)
  }

  /**
   * With registered routes: a shared unit's operand as [[bySource]] gives it, two clocks later, through two
   * registered multiplexer levels. The sources in groups ([[ArmDatapath.routeGroups]]), each group's
   * multiplexer into a register of its own (the placer puts it beside its sources), then the groups'
   * registers into the operand register beside the unit. The source read in residue r is in its group's
   * register in r + 1 and in the operand register in r + 2.
   */
  private def bySourceRouted(sources: Seq[PortSource], entries: Seq[(Int, PortSource, SInt)]): SInt = {
    val (inputs, index) = sourcesByResidue(sources, entries)
    val width = inputs.map(_.getWidth).max
    def register(v: SInt): SInt = FixedHw.delay(v.pad(width), 1)
    val grouping = ArmDatapath.routeGroups(sources)
    val groupOf = grouping.zipWithIndex.flatMap { case (members, g) => members.map(_ -> g) }.toMap
    // A select of its own per slice of a register: the bits of a group register sit beside their own sources,
    // and a select decode shared by all bits of the operand register was a route across the chip.
    val slices = (0 until width).grouped(ArmDatapath.selectSliceBits).toSeq
    def sliced(options: Seq[SInt], table: IndexedSeq[Int]): SInt = {
      val selects = decodedAhead(table, slices.size)
      Cat(slices.zip(selects).reverse.map { case (bits, select) =>
        VecInit(options.map(_.pad(width).asUInt(bits.last, bits.head)))(select)
      }).asSInt
    }
    val groups = grouping.zipWithIndex.map { case (members, g) =>
      // in residue r the member read then, or the one it took last (its register is not read meanwhile)
      val member = (0 until ii)
        .scanLeft(0)((prev, r) => if (groupOf(index(r)) == g) members.indexOf(index(r)) else prev)
        .tail
      register(if (members.size == 1) inputs(members.head) else sliced(members.map(inputs), member))
    }
    // in residue r the operand register takes the group of the source read in r - 1
    register(
      if (groups.size == 1) groups.head
      else sliced(groups, (0 until ii).map(r => groupOf(index((r + ii - 1) % ii))))
    )
  }

  /**
   * Kept copies of the phase flags, handed out one residue at a time, each copy serving `fanout` takers in
   * the order they ask; `copy(r)` builds residue r's.
   */
  private final class FlagCopies(fanout: Int, copy: Int => Bool) {
    private val handed = Array.fill(ii)(0)
    private val copies = scala.collection.mutable.Map.empty[(Int, Int), Bool]
    def apply(r: Int): Bool = {
      val n = handed(r)
      handed(r) = n + 1
      copies.getOrElseUpdate((r, n / fanout), copy(r))
    }
  }

  /**
   * The phase flags the selects' decodes read with registered routes: each a kept copy of the ring's flag,
   * shared by the partial ORs of up to [[ArmDatapath.decodeFanout]] decodes in the order they are built (a
   * unit's ports, one after the other). Read straight from the ring, synthesis built the partial ORs of
   * selects across the chip from each other's terms (a flag and the reset in a LUT shared by tens of
   * partials, ORs of more flags chained from it): two to four LUTs apart by long routes, the limit of several
   * runs (docs/timing-closure.md). A copy is a ring stage (the flag of the residue before, a clock later, the
   * ring's reset value), so every decode is as before, cycle for cycle.
   */
  private lazy val decodeFlags =
    new FlagCopies(
      ArmDatapath.decodeFanout,
      r => FixedHw.kept(RegNext(phaseIs((r + ii - 1) % ii), (r == 0).B))
    )

  /**
   * A register whose value in residue r is `table(r)`, decoded from the phase flags two clocks ahead: each
   * bit the OR of up to four flags into a register, then the OR of those into the select. No select waits on
   * a decode of flags from across the chip (with registered routes those paths limit the clock next). With
   * several `copies`, each select register is kept apart (one per slice of a wide register it steers). The
   * partial ORs are kept too, each select's its own: synthesis merges equal ones across selects, and a shared
   * partial OR reaching the selects of several groups across the chip limited the clock (timing-closure.md).
   * They cost few logic elements (each packs with a LUT), so the resource prediction leaves them out, and the
   * flags' copies too ([[ArmDatapath.decodeFanout]]).
   */
  private def decodedAhead(table: IndexedSeq[Int], copies: Int): Seq[UInt] = {
    // one copy of each flag for all of this decode's partial ORs
    val taken = scala.collection.mutable.Map.empty[Int, Bool]
    def flag(r: Int) = taken.getOrElseUpdate(r, decodeFlags(r))
    val bits = (0 until log2Ceil(table.max + 1).max(1)).map { b =>
      def set(r: Int) = (table(r % ii) >> b & 1) == 1
      val residues = (0 until ii).filter(r => set(r + 2))
      if (residues.isEmpty) Seq.fill(copies)(false.B)
      else {
        // in residue r: whether residue r - 1 is one of the group's (in cycle 0: residue II - 1)
        val partial =
          residues
            .grouped(4)
            .toSeq
            .map(g => FixedHw.kept(RegNext(g.map(flag).reduce(_ || _), g.contains(ii - 1).B)))
        val select = partial.reduce(_ || _)
        if (copies == 1) Seq(RegNext(select, set(0).B))
        else Seq.fill(copies)(FixedHw.kept(RegNext(select, set(0).B)))
      }
    }
    (0 until copies).map(k => VecInit(bits.map(_(k))).asUInt)
  }

  /**
   * One write pointer per length of block-RAM delay of held values, shared by every delay of that length;
   * with registered routes one per delay, kept beside its block RAM (a shared pointer, pulled toward block
   * RAMs across the chip, had its own increment far from it and limited the clock: docs/timing-closure.md,
   * "The device fit's designs route").
   */
  private val delayPointers = scala.collection.mutable.Map.empty[Int, DelayPointer]
  private def delayPointer(cycles: Int): DelayPointer =
    if (schedule.routed) new DelayPointer(cycles, kept = true)
    else delayPointers.getOrElseUpdate(cycles, new DelayPointer(cycles))

  /** Registers of a registered select's lookup ROM: its block RAM's read and output registers. */
  private val romRegisters = 2

  /**
   * Cycles a registered select is looked up ahead of its use: the ROM's registers, the register in the fabric
   * and the slice's copy.
   */
  private val selectAhead = romRegisters + 2

  /** True in cycle `cycle` of every sample (and in every cycle at II = 1). */
  private def during(cycle: Int): Bool = phaseIs(cycle % ii)

  /** Routes between value registers and shared units pass registers (`datapath.registered-routes`). */
  private val routed = schedule.routed

  /** First-level copies of the phase flags the held registers' enables come from ([[enableIn]]). */
  private lazy val firstLevelEnables = new FlagCopies(
    ArmDatapath.enableFanout,
    r => FixedHw.kept(RegNext(phaseIs((r + ii - 2) % ii), ((r + ii - 1) % ii == 0).B))
  )

  /**
   * The write enable of a held register written in cycle `cycle`: [[during]], or with registered routes a
   * kept copy of the phase flag of its own, from a kept copy per [[ArmDatapath.enableFanout]] registers, so
   * that no flag reaches hundreds of registers across the chip. Each copy is the flag two (one) clocks late
   * of the residue two (one) before, its reset value the flag's in cycle 0.
   */
  private def enable(cycle: Int): Bool = enableIn(Seq(cycle))

  /**
   * The write enable of a register written in each of `cycles` (a [[reducerload.graph.SharedRegister]]): the
   * OR of their flags, with registered routes into the register's own copy.
   */
  private def enableIn(cycles: Seq[Int]): Bool = {
    val residues = cycles.map(_ % ii).distinct
    if (!routed) residues.map(phaseIs).reduce(_ || _)
    else {
      val firsts = residues.map(firstLevelEnables(_))
      FixedHw.kept(RegNext(firsts.reduce(_ || _), residues.contains(0).B))
    }
  }

  /**
   * `stage0`, a register written at the end of cycle `ready - 1` of every sample, as seen in each cycle of
   * `reads`: one delay line at II = 1, else a chain of registers written at the same phase, long stretches of
   * either in block RAM ([[HeldTaps]]).
   */
  private def held[T <: Data](
      stage0: T,
      ready: Int,
      reads: Seq[Int],
      inBlockRam: Boolean = true
  ): Map[Int, T] = {
    require(
      reads.forall(_ >= ready),
      s"ArmDatapath: a value ready in cycle $ready is read earlier, in ${reads.min}"
    )
    if (ii == 1)
      reads.distinct.sorted
        .foldLeft((Map.empty[Int, T], stage0, ready)) { case ((taps, v, t), r) =>
          val d =
            if (MemoryDelay.inBlockRam(r - t, p.memoryDelayMinCycles)) {
              val fabric = ArmDatapath.delayFabricRegisters(schedule, r - t)
              MemoryDelay.shared(v, delayPointer(r - t - fabric), fabric)
            } else FixedHw.delay(v, r - t)
          (taps + (r -> d), d, r)
        }
        ._1
    else {
      // memory storage keeps its few held values (angles, flags) in registers: its block RAM is its banks'
      val taps = HeldTaps(ii, ready, reads, if (p.banked.isEmpty && inBlockRam) p.memoryDelayMinCycles else 0)
      val stages = (1 to taps.chain).scanLeft(stage0)((prev, _) => RegEnable(prev, enable(ready - 1)))
      val delayed = taps.delayed.map { k =>
        val fabric = ArmDatapath.delayFabricRegisters(schedule, k * ii)
        k -> MemoryDelay.shared(stage0, delayPointer(k * ii - fabric), fabric)
      }.toMap
      reads.map { r =>
        val k = (r - ready) / ii
        r -> delayed.getOrElse(k, stages(k))
      }.toMap
    }
  }

  io.in.ready := during(0)
  private val accept = io.in.valid && io.in.ready
  // With registered routes each input register has its own copy of the flag (`enable`): io.in.ready into
  // every clamp's set and reset across the chip limited the clock next.
  private val angles = RegEnable(io.in.bits.q, enable(0))

  // Cycle 0: velocities and accelerations clamped to the declared ranges straight from the port, in
  // each joint's own format, into their registers for cycle 1 (a register before the clamp would
  // hold every one twice). Registers storage reads them all interval long: they take the port when
  // a sample is. Memory storage loads them into its input chain in cycle 1: they take the port every
  // clock, so the clamp's set and reset of the registers do not wait on the phase (the flag of
  // residue 0 into the clamp's reset goes through a LUT the placer puts far from both).
  private def clamp(x: SInt, limit: BigInt, width: Int): (SInt, Bool) = clampTo(x, -limit, limit, width)
  private def clampTo(x: SInt, lo: BigInt, hi: BigInt, width: Int): (SInt, Bool) = {
    val (value, outside) = FixedHw.clamp(x, lo, hi, width)
    if (p.banked.isDefined) (RegNext(value), RegNext(outside))
    else (RegEnable(value, enable(0)), RegEnable(outside, enable(0)))
  }
  private val velocities = (0 until joints).map(j =>
    clamp(io.in.bits.qd(j), numerics.velocityLimitRaw(j), numerics.velocityFormats(j).width)
  )
  private val accelerations = (0 until joints).map(j =>
    clamp(io.in.bits.qdd(j), numerics.accelerationLimitRaw(j), numerics.accelerationFormats(j).width)
  )
  // The payload's parameters, each clamped to its declared interval like the velocities: with the sample.
  private val parameters: Map[Signal.Parameter, (SInt, Bool)] = numerics.parameters.zipWithIndex.map {
    case (s, k) =>
      val (lo, hi) = numerics.parameterLimitRaw(s)
      s -> clampTo(io.in.bits.payload.get(k), lo, hi, numerics.parameterFormats(s).width)
  }.toMap
  require(schedule.inputCycle == ArmDatapath.inputCycle, "the input stage above is one register deep")
  // Cycle 1: one flag per joint (the two compares are registered apart, so their OR has a clock of its own);
  // a clamped payload parameter changes every torque, so it flags every joint.
  private val payloadOutside: Option[Bool] =
    Option.when(parameters.nonEmpty)(numerics.parameters.map(parameters(_)._2).reduce(_ || _))
  private val jointFlagRegisters = (0 until joints).map { j =>
    val inputs = velocities(j)._2 || accelerations(j)._2
    RegEnable(payloadOutside.fold(inputs)(inputs || _), enable(ArmDatapath.inputCycle))
  }

  // Angles: each joint's code from the input register, at the cycles its sums are issued.
  private val angleTaps = (0 until joints).map(j => held(angles(j), 1, schedule.angleReads(j)))
  // Each angle sum at its issue: added from the taps its register stages before (Schedule.angleSumStages).
  private def angleSum(angle: AngleSum): UInt = {
    val stages = schedule.angleSumStages(angle)
    val cycle = schedule.angleSlot(angle).issue - stages
    val sum = angle.terms.foldLeft(0.U(numerics.angleBits.W)) { case (acc, (j, k)) =>
      // binary angles wrap modulo one turn, as angles do
      (0 until k.abs).foldLeft(acc)((a, _) =>
        if (k > 0) a +% angleTaps(j)(cycle) else a -% angleTaps(j)(cycle)
      )
    }
    ShiftRegister(sum, stages)
  }
  private val cordicOutputs = schedule.cordicBindings.map { bound =>
    val unit = Module(new CordicSinCos(schedule.cordic))
    val sums = bound.map { case (residue, angle) =>
      residue -> angleSum(angle)
    }
    // no data register waits on valid; the datapath's own valid chain says which samples count
    unit.io.in.valid := true.B
    // Memory storage and registered routes: the select registered (its route reaches across the larger
    // designs; with registered routes a phase decode, and then a select decoded from the scattered phase
    // flags, limited the clock next); registers storage keeps the phase-decoded one, which does not limit
    // the clock of its designs.
    unit.io.in.bits := RegNext(
      if (p.banked.isDefined || routed) byPhaseRegistered(sums) else byPhase(sums)
    )
    unit.io.out.bits
  }

  private def signal(s: Signal): SInt = s match {
    case Signal.Velocity(j)     => velocities(j)._1
    case Signal.Acceleration(j) => accelerations(j)._1
    case s: Signal.Parameter    => parameters(s)._1
  }

  private val outAt = p.outputsReady

  /** Each output's value in cycle `outAt`, from the storage the schedule asks for. */
  private val outputValues: IndexedSeq[SInt] = p.banked match {
    case Some(banked) =>
      new MemoryStorage(p, banked, residueCounter, during, held[SInt](_, _, _), signal, cordicOutputs).outputs
    case None => registerStorage()
  }

  /**
   * Every value in its own registers (or products taking turns in a shared one), each unit operand selected
   * among them by the phase.
   */
  private def registerStorage(): IndexedSeq[SInt] = {
    // Multiplier units: products wired in after every operand exists.
    def shapeOfUnit(u: Int): MulShape = schedule.unitShape(u)
    val products =
      schedule.mulBindings.indices.map(u => Wire(SInt(shapeOfUnit(u).productBits.W)))
    // A product of multiply `id` (the product rule) at `width` bits.
    def rounded(product: SInt, id: NodeId, width: Int): SInt = {
      val rule = analysis.productRounding(id)
      FixedHw.fitWidth(FixedHw.shiftRound(product, rule.drop, rule.rounding), width)
    }
    // Registers products take turns in: the members' rounding (one for all) at the widest member's width,
    // written at each member's phase.
    val shared: Map[reducerload.graph.SharedRegister, SInt] = schedule.sharedRegisters.map { r =>
      r -> RegEnable(
        rounded(products(r.unit), r.members.head, r.width),
        enableIn(r.members.map(schedule(_).get - 1))
      )
    }.toMap

    /**
     * Each unit's product memory ([[reducerload.graph.ProductMemory]]), its word as read: the unit's product
     * bits written every clock at the slot of the cycle's residue (a counter of its own), the slot a read
     * needs decoded from the phase flags into the block RAM's address [[ProductMemory.readDelay]] clocks
     * before the read's cycle, the word through the block RAM's output register into a register in logic in
     * that cycle.
     */
    val memoryWords: Map[ProductMemory, SInt] = schedule.productMemories.map { m =>
      val memory = SyncReadMem(ii, UInt(m.width.W))
      memory.write(residueCounter(0), products(m.unit)(m.high - 1, m.low))
      // in residue r the slot of the member read in cycle r + readDelay (residues no read takes: slot 0)
      val slots = (0 until ii).map(r =>
        m.members
          .find(_.reads.exists(c => (c - ProductMemory.readDelay) % ii == r))
          .fold(0)(_.slot(ii))
      )
      // the read is the address register's clock; the output register and those in logic follow
      m -> FixedHw.delay(memory.read(decodedAhead(slots, 1).head), ProductMemory.readDelay - 1).asSInt
    }.toMap

    /**
     * Each CORDIC unit's sin / cos memory ([[reducerload.graph.SinCosMemory]]), its word as read: the unit's
     * output written every clock at a pointer of its own (a counter modulo the depth, so the memory, its
     * pointer and its subtraction can sit together), read at the pointer minus how far back the value read
     * [[ProductMemory.readDelay]] clocks later was written (decoded from the phase flags as the product
     * memories' slots are), through the block RAM's output register into a register in logic in that cycle.
     */
    val sinCosWords: IndexedSeq[SInt] = schedule.sinCosMemories.map { m =>
      val out = cordicOutputs(m.unit)
      val v = (if (m.fn == TrigFn.Cos) out.cos else out.sin).asUInt
      val memory = SyncReadMem(SinCosMemory.depth, UInt(v.getWidth.W))
      val bits = log2Ceil(SinCosMemory.depth)
      val pointer = RegInit(0.U(bits.W))
      pointer := pointer + 1.U
      memory.write(pointer, v)
      // in residue r how far back the value read in cycle r + readDelay was written (residues no read takes: 0)
      val back = (0 until ii).map(r =>
        m.reads.find(o => (o.cycle - ProductMemory.readDelay) % ii == r).fold(0)(_.back)
      )
      val address = (pointer - decodedAhead(back, 1).head)(bits - 1, 0)
      FixedHw.delay(memory.read(address), ProductMemory.readDelay - 1).asSInt
    }

    /** `v`, with `fracBits` fraction bits, raised to `f`'s (exactly) and sign-extended to `f`'s width. */
    def alignedTo(v: SInt, fracBits: Int, f: FixedFormat): SInt =
      (v << (f.fracBits - fracBits)).asSInt.pad(f.width)

    /**
     * Each unit's registers of rounded products for the accumulators ([[reducerload.graph.Accumulation]]):
     * one per rounding its accumulated products take, as wide as the widest of them (a narrower one's value
     * fits, so its bits are the same), loaded every clock. A product is in it in the cycle its own register
     * would hold it.
     */
    val roundedForAccumulators: Map[(Int, ProductRounding), SInt] =
      schedule.accumulations
        .flatMap(_.products)
        .groupBy(id => (schedule.slot(id).get.unit.get, analysis.productRounding(id)))
        .map { case (key @ (unit, _), ids) =>
          val width = ids.map(analysis(_).format.width).max
          key -> RegNext(rounded(products(unit), ids.head, width))
        }

    /**
     * The root's register of an accumulated tree ([[reducerload.graph.Accumulation]]): each product, from its
     * unit's register of rounded products, aligned to the root's fraction bits and complemented where the
     * tree subtracts it, into the accumulator's term register, and from there into one adder with the partial
     * sum (none with the first product; a subtracted one's carry in); the accumulator takes every sum, the
     * root's register the last. Products of one unit rounded alike are one input of the term's selection.
     */
    def accumulate(a: Accumulation): SInt = {
      val f = analysis(a.root).format
      // each product in its unit's register of rounded products in the cycle it would be in one of its own
      def out(t: Accumulation.Term) = schedule(t.product).get
      val terms = a.terms.sortBy(out)
      def alike(t: Accumulation.Term) =
        (schedule.slot(t.product).get.unit.get, analysis.productRounding(t.product))
      val inputs = terms.map(alike).distinct.map { key =>
        val fracBits = analysis(terms.find(alike(_) == key).get.product).format.fracBits
        key -> alignedTo(roundedForAccumulators(key), fracBits, f)
      }
      val term = inputs.tail.foldLeft(inputs.head._2) { case (other, (key, v)) =>
        Mux(enableIn(terms.filter(alike(_) == key).map(out)), v, other)
      }
      val negated = terms.filter(_.negated).map(out)
      val subtract =
        if (negated.isEmpty) false.B else if (negated.size == terms.size) true.B else enableIn(negated)
      // a subtraction as the complement and a carry in, so that one adder does both; the term's register
      // keeps the selection and the complement out of the adder's clock, which the UR5's clock needed
      // (docs/timing-closure.md), so each product is added the clock after it is in its unit's register
      val complemented = ShiftRegister(term.asUInt ^ Fill(f.width, subtract), Accumulation.termRegisters)
      val carryIn = ShiftRegister(subtract, Accumulation.termRegisters)
      def added(t: Accumulation.Term) = out(t) + Accumulation.termRegisters
      // The accumulator's enable before the accumulator: firtool 1.62 lowers registers in the module's order
      // and caches each `if` by its condition's value, so an enable register declared after the register it
      // enables leaves a stale condition that another register's enable can take (docs/design.md).
      val load = enableIn(terms.init.map(added))
      val accumulator = Reg(SInt(f.width.W)) // no reset: the first product replaces it
      val base = Mux(enable(added(terms.head)), 0.S(f.width.W), accumulator)
      val sum = (base.asUInt + complemented + carryIn.asUInt)(f.width - 1, 0).asSInt
      when(load)(accumulator := sum)
      RegEnable(sum, enable(added(terms.last)))
    }

    // The graph, node by node: each value's register and the taps its readers use.
    val values: Vector[Map[Int, SInt]] = graph.ids.foldLeft(Vector.empty[Map[Int, SInt]]) { (done, id) =>
      val f = analysis(id).format
      def tap(x: NodeId, cycle: Int): SInt = graph(x) match {
        case Const(_) => constant(x)
        case _        => done(x.index)(cycle)
      }

      /** Operand `x` in cycle `t`, its fraction bits raised to `f`'s, sign-extended to `f`'s width. */
      def aligned(x: NodeId, t: Int): SInt = alignedTo(tap(x, t), analysis(x).format.fracBits, f)
      def fit(v: SInt): SInt = FixedHw.fitWidth(v, f.width)
      val ready = schedule(id)
      def issue = schedule.slot(id).get.issue
      def register(v: SInt, cycle: Int): SInt = RegEnable(fit(v), enable(cycle))

      /** The value's register, seen by its readers. */
      def kept(stage0: SInt): Map[Int, SInt] = held(stage0, ready.get, schedule.reads(id.index))
      val taps: Map[Int, SInt] = graph(id) match {
        case Add(_, _) | Sub(_, _) | Mul(_, _) if schedule.accumulation(id).isDefined =>
          // an accumulated tree: its root's register, no register for its products and inner sums
          schedule.accumulation(id).filter(_.root == id).fold(Map.empty[Int, SInt])(a => kept(accumulate(a)))
        case Const(_)                      => Map.empty
        case Input(Signal.Velocity(j))     => kept(velocities(j)._1)
        case Input(Signal.Acceleration(j)) => kept(accelerations(j)._1)
        case Input(s: Signal.Parameter)    => kept(parameters(s)._1)
        case Trig(fn, a) =>
          val out = cordicOutputs(schedule.angleSlot(a).unit.get)
          val v = if (fn == TrigFn.Cos) out.cos else out.sin
          // reads a sin/cos memory serves take its word; the others the value's register, if any are left
          val own = schedule.ownReads(id)
          val fromMemory = schedule
            .reads(id.index)
            .filterNot(own.contains)
            .map(c => c -> sinCosWords(schedule.sinCosMemoryOf((id, c))))
          (if (own.isEmpty) Map.empty[Int, SInt]
           else
             held(if (schedule.capturesCordic) RegEnable(v, enable(ready.get - 1)) else v, ready.get, own)) ++
            fromMemory
        case Add(a, b) => kept(register(aligned(a, issue) + aligned(b, issue), issue))
        case Sub(a, b) => kept(register(aligned(a, issue) - aligned(b, issue), issue))
        case Neg(a)    => kept(register(-aligned(a, issue), issue))
        case Mul(_, _) if schedule.productMemoryOf.contains(id) =>
          // the word back at its place in the product (the bits below it are ones the members' rounding
          // drops), through the member's rule: its own register's bits, in each cycle it is read
          val m = schedule.productMemoryOf(id)
          val v = rounded(memoryWords(m) << m.low, id, f.width)
          schedule.reads(id.index).map(_ -> v).toMap
        case Mul(_, _) =>
          val rule = analysis.productRounding(id)
          val product =
            if (schedule.shiftAdded(id)) {
              val (x, constant) = schedule.shiftAddOperands(id)
              ShiftAddMultiplier(tap(x, issue), constant)
            } else products(schedule.slot(id).get.unit.get)
          val own = rounded(product, id, f.width)
          val captured = !schedule.dedicated || rule.rounding != Rounding.Truncate
          if (schedule.forwarded(id))
            Map(ready.get - 1 -> own) // its one reader takes it off the unit's output
          else
            schedule.sharedRegisterOf.get(id) match {
              case Some(r) => kept(fit(shared(r)))
              case None    => kept(if (captured) RegEnable(own, enable(ready.get - 1)) else own)
            }
      }
      done :+ taps
    }

    // Readers' copies (`schedule.reader-copies`): each loaded a clock after the value's register, so it holds
    // the value in the cycles its unit reads it (all after the one it is ready in: Schedule.readerCopies).
    val copies: Map[(NodeId, Int), SInt] = schedule.readerCopies.toSeq.flatMap { case (x, units) =>
      val ready = schedule(x).get
      val register = values(x.index).collectFirst { case (t, v) if t - ready < ii => v }.get
      units.map(u => (x, u) -> FixedHw.kept(RegEnable(register, enable(ready))))
    }.toMap
    schedule.mulBindings.zipWithIndex.foreach { case (bound, u) =>
      val shape = shapeOfUnit(u)
      def port(k: Int, width: Int): SInt = (if (routed) bySourceRouted _ else bySource _) (
        schedule.portSources(u)(k),
        bound.map { case (r, id) =>
          val x = schedule.ports(id)(k)
          val issue = schedule.slot(id).get.issue
          (
            r,
            schedule.muxSource(x, issue),
            (graph(x) match {
              case Const(_)                             => constant(x)
              case _ if schedule.readsCopy(x, u, issue) => copies((x, u))
              case _                                    => values(x.index)(issue)
            }).pad(width)
          )
        }
      )
      val product = PipelinedMultiplier(port(0, shape.wide), port(1, shape.narrow))
      products(u) := FixedHw.delay(product, p.multiplierLatency - 1)
    }
    // An output may be a constant (a joint whose torque folds to zero: nothing it moves has mass).
    graph.outputs.map(o =>
      graph(o.node) match {
        case Const(_) => constant(o.node)
        case _        => values(o.node.index)(outAt)
      }
    )
  }

  /** A constant node's code: a literal, no register. */
  private def constant(x: NodeId): SInt = analysis(x).raw.get.S(analysis(x).format.width.W)

  // Output stage: each torque rounded half up to the output format and saturated, the saturation
  // decided on the unrounded value beside the rounding adder (FixedHw.roundSaturateDecision); then
  // every joint's flag ORs in the saturation of any torque. Registers storage: two registers deep
  // (Schedule.outputStages), the bound multiplexer before the first (rounding, saturation and the
  // OR across the joints in one clock would be too long a path). Memory storage and registered
  // routes: three (BankedSchedule.outputStages), the compares registered before the multiplexer and
  // the OR registered before the flags, so that neither limits the faster clock those designs reach.
  require(
    p.latency == outAt + p.outputStages,
    s"ArmDatapath: latency ${p.latency} is not the output stage's ${p.outputStages} cycles after cycle $outAt"
  )
  private val decisions = graph.outputs.zip(analysis.outputs).zip(outputValues).map { case ((o, info), v) =>
    FixedHw.roundSaturateDecision(v, analysis.outputDrop(o), info.format)
  }
  private def portCode(decided: Clamped): SInt = decided.value.pad(analysis.outputPortFormat.width)

  /** Each joint's input flag as read in cycle `cycle` of the output stage. */
  private def jointFlags(cycle: Int): Seq[Bool] =
    jointFlagRegisters.map(flag => held(flag, ArmDatapath.flagCycle, Seq(cycle), inBlockRam = false)(cycle))
  private val outBits = Reg(new ArmOutput(p)) // data: no reset; `valid` says when it counts
  if (p.outputStages == Schedule.outputStages) {
    val results =
      decisions.map(d => (RegEnable(portCode(d), during(outAt)), RegEnable(d.outside, during(outAt))))
    val flagged = jointFlags(outAt).map(RegEnable(_, during(outAt)))
    val anySaturated = results.map(_._2).reduce(_ || _)
    when(during(outAt + 1)) {
      outBits.tau := VecInit(results.map(_._1))
      outBits.outOfRange := VecInit(flagged.map(_ || anySaturated))
    }
  } else {
    require(
      p.outputStages == BankedSchedule.outputStages && ii >= 2,
      "ArmDatapath: a three-register output stage holds the torques a cycle: it needs II >= 2"
    )
    // The torques' port registers are loaded a cycle before the flags' and held (II >= 2) until then.
    val registered = decisions.map(_.registered(during(outAt)))
    val anySaturated = RegEnable(registered.map(_.outside).reduce(_ || _), during(outAt + 1))
    when(during(outAt + 1))(outBits.tau := VecInit(registered.map(portCode)))
    when(during(outAt + 2))(outBits.outOfRange := VecInit(jointFlags(outAt + 2).map(_ || anySaturated)))
  }
  io.out.bits := outBits
  io.out.valid := (if (ii == 1) ShiftRegister(accept, p.latency, false.B, true.B) else acceptedLatencyAgo)

  /**
   * `accept`, `p.latency` cycles later, at II >= 2. Samples enter in residue 0 only, so the ones in flight
   * are the bits of a register chain shifted once per sample interval, and the phase tells in which cycle of
   * its stretch the last bit is the output's: about latency / II registers where a delay line takes one per
   * cycle. The flag is registered, decided in the cycle before the output's.
   */
  private def acceptedLatencyAgo: Bool = {
    val before = p.latency - 1
    require(before >= 1, s"ArmDatapath: latency ${p.latency} leaves no cycle to decide the output's valid in")
    // A sample accepted in cycle c is in chain register k during cycles c + k * II + 1 .. c + (k + 1) * II.
    val chain = ShiftRegister(accept, (before - 1) / ii + 1, false.B, during(0))
    RegNext(chain && during(before), false.B)
  }
}

object ArmDatapath {

  /**
   * Registers in logic after a block-RAM delay of `cycles` clocks of a held value, the delay a clock shorter
   * in block RAM: one with registered routes or at one sample per clock, where the block RAM keeps its
   * shortest delay. The block RAM's own output register sits by the block RAM, and its word went across the
   * chip into a reader's group multiplexer (the README's UR5 on three seeds of four) or, at one sample per
   * clock, through a LUT into a far multiplier's input register (the joint-3 default on seed 1):
   * docs/timing-closure.md, "a register after each block-RAM delay" and "a register after the block-RAM
   * delays at one sample per clock"; a register in logic is placed toward the readers.
   */
  def delayFabricRegisters(s: Schedule, cycles: Int): Int =
    if ((s.routed || s.clocksPerSample == 1) && cycles - 1 >= MemoryDelay.minCycles) 1 else 0

  /** Sources per first-level multiplexer with registered routes: a 4:1 multiplexer is two LUT4s per bit. */
  val routeGroup: Int = 4

  /**
   * A port's sources (indices into `sources`) in the first-level groups of registered routes: held values and
   * literals in groups of their own. A literal among held values would let synthesis turn its select into the
   * group register's synchronous set and reset, a net that reaches every bit of the register, which sit
   * beside their own sources across the chip (it limited the UR5's clock: docs/timing-closure.md).
   */
  def routeGroups(sources: Seq[reducerload.graph.PortSource]): Seq[Seq[Int]] = {
    val (literals, held) =
      sources.indices.partition(k => sources(k).isInstanceOf[reducerload.graph.PortSource.Literal])
    held.grouped(routeGroup).toSeq ++ literals.grouped(routeGroup).toSeq
  }

  /**
   * Bits of a first-level group register, or of a CORDIC unit's input, steered by one copy of its select with
   * registered routes: the bits of one register sit beside their own sources, so one select reaching all of
   * them crosses the chip (the UR5's limiting paths before the copies: docs/timing-closure.md).
   */
  val selectSliceBits: Int = 8

  /**
   * Select register bits of a multiplexer of `members` options into a `width`-bit register (either level).
   */
  def groupSelectBits(width: Int, members: Int): Int =
    if (members <= 1) 0 else reducerload.util.IntMath.ceilDiv(width, selectSliceBits) * log2Ceil(members)

  /**
   * Select decodes served by one copy of a phase flag with registered routes (the datapath's `decodeFlags`):
   * the only value measured; its logic elements and the paths it took off the limit are in
   * docs/timing-closure.md ("the select decode's flags").
   */
  val decodeFanout: Int = 4

  /** Held registers served by one first-level copy of a phase flag with registered routes. */
  val enableFanout: Int = 16

  /**
   * Longest interval whose phase flags come from a ring: a ring costs II flip-flops, a logic element each,
   * against the counter's compares, so a long ring costs more logic than it saves; the designs whose clock
   * the flags limit run at tens of clocks per sample.
   */
  val ringMaxInterval: Int = 128

  /** Cycle at which the clamped velocities and accelerations are in registers. */
  val inputCycle: Int = 1

  /** Cycle at which each joint's out-of-range flag is in its register. */
  val flagCycle: Int = inputCycle + 1
}
