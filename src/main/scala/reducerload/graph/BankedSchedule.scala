package reducerload.graph

import reducerload.util.IntMath.ceilDiv

/** Where a shared datapath keeps its values between operations (`schedule.storage`). */
sealed abstract class Storage(val name: String) { override def toString: String = name }
object Storage {

  /** Every value in its own registers; each unit operand selects among them by the phase ([[Schedule]]). */
  case object Registers extends Storage("registers")

  /**
   * Values in block-RAM banks, one bank per producing unit, read by addresses from a table indexed by the
   * phase; additions share adder units too ([[BankedSchedule]]).
   */
  case object Memory extends Storage("memory")

  val all: Seq[Storage] = Seq(Registers, Memory)
}

/** A unit whose results are written into one bank (each writes at most one result per clock). */
sealed trait Bank
object Bank {

  /** The clamped velocities and accelerations, one per clock after the input stage. */
  case object Inputs extends Bank
  final case class Products(unit: Int) extends Bank
  final case class Sums(unit: Int) extends Bank
  final case class Trig(unit: Int, fn: TrigFn) extends Bank
}

/** An operand of a shared unit: a value read from its bank, a constant of the graph, or zero. */
sealed trait Operand {

  /** The graph node it carries (None: zero). */
  def carried: Option[NodeId] = this match {
    case Operand.Stored(n, _) => Some(n)
    case Operand.Forwarded(n) => Some(n)
    case Operand.Constant(n)  => Some(n)
    case Operand.Zero         => None
  }
}
object Operand {

  /** Read from its bank, on the bank's read port `port` (0 or 1; each unit operand may take either). */
  final case class Stored(node: NodeId, port: Int = 0) extends Operand

  /** Taken from its unit's output register in the one cycle it is there (no bank read). */
  final case class Forwarded(node: NodeId) extends Operand
  final case class Constant(node: NodeId) extends Operand
  case object Zero extends Operand
}

/**
 * The order a list scheduler places operations in (`schedule.list-order`; auto: the one with the least
 * latency). Each leaves some intervals' latency far above the dependences' bound where the other does not
 * (list scheduling is a heuristic), and each schedules some tight intervals the other cannot.
 */
sealed abstract class ListOrder(val name: String) { override def toString: String = name }
object ListOrder {

  /**
   * Cycle by cycle, each cycle's ready operations highest first: a value is used as soon as a unit is free.
   */
  case object ByCycle extends ListOrder("by-cycle")

  /**
   * Operation by operation, highest first (a topological order: every operation is higher than its users),
   * each at its first free cycle: the critical path claims its residues before the operations with slack fill
   * the rest. On the larger arms it gives the lower latency, and perturbed tries (`schedule.list-tries`)
   * lower it further.
   */
  case object ByHeight extends ListOrder("by-height")
  val all: Seq[ListOrder] = Seq(ByHeight, ByCycle)
}

/** The two kinds of shared arithmetic unit besides the CORDIC units. */
sealed trait UnitKind
object UnitKind {
  case object Multiplier extends UnitKind
  case object Adder extends UnitKind
}

/**
 * One multiply or addition on a unit: it reads `operands` (port 0, port 1) in cycle `issue`; an adder
 * computes port 0 + port 1, or port 0 - port 1 when `subtract`.
 */
final case class PlacedOp(
    node: NodeId,
    kind: UnitKind,
    unit: Int,
    issue: Int,
    operands: IndexedSeq[Operand],
    subtract: Boolean
)

/** A bank read: `node` on read port `port` of `bank`, its address presented in cycle `cycle`. */
final case class BankRead(node: NodeId, bank: Int, port: Int, cycle: Int)

/**
 * What an operation runs on: its unit kind, units, result latency and bank per unit; `lead`: cycles from a
 * bank read's address to the issue, `forwardLead`: from a value's ready cycle to an issue that takes it from
 * its unit's output register.
 */
private final case class Kind(
    kind: UnitKind,
    units: Range,
    lead: Int,
    forwardLead: Int,
    shape: Int => Option[MulShape],
    latency: Int,
    bank: Int => Bank
)

/** A unit at one residue of the phase: it takes one operation there. */
private final case class UnitSlot(kind: UnitKind, unit: Int, residue: Int)

/** A bank's read port at one residue of the phase: it takes one address there. */
private final case class ReadSlot(bank: Int, port: Int, residue: Int)

/** An operand port (0 or 1) of a unit: one multiplexer over its sources. */
private final case class UnitPort(kind: UnitKind, unit: Int, port: Int)

/**
 * The banked list scheduler's state after each node: ready cycles, banks, placements, taken unit and
 * read-port residues (with the read that takes each), reads, and the sources each unit port selects among so
 * far.
 */
private final case class BankedState(
    ready: Vector[Option[Int]],
    bank: Vector[Option[Int]],
    placed: Vector[Option[PlacedOp]],
    units: Set[UnitSlot],
    ports: Map[ReadSlot, BankRead],
    reads: Vector[BankRead],
    sources: Map[UnitPort, Set[OperandSource]] = Map.empty
)

/**
 * Where a unit port's operand comes from: a bank's read port, a unit's output register, or the table (a
 * constant or zero). Each distinct source is one input of the port's multiplexer.
 */
sealed trait OperandSource
object OperandSource {
  final case class ReadPort(bank: Int, port: Int) extends OperandSource
  final case class Output(bank: Int) extends OperandSource
  case object Table extends OperandSource

  /** The source of `operand`, with `bankOf` the bank of each stored node. */
  def of(operand: Operand, bankOf: NodeId => Int): OperandSource = operand match {
    case Operand.Stored(x, port) => ReadPort(bankOf(x), port)
    case Operand.Forwarded(x)    => Output(bankOf(x))
    case _                       => Table
  }

  /**
   * Integers in the order of their decimal text ("10" before "2"), for the multiplexer order below.
   */
  val decimalTextOrder: Ordering[Int] = Ordering.by(_.toString)

  /**
   * The order of a unit port's multiplexer inputs in the memory-storage datapath: read ports, then output
   * registers, then the table; each by bank, then by port, the numbers compared as decimal text. The sources
   * were first sorted by their text, and the emitted Verilog (the order of the multiplexers' inputs and of
   * their registers' declarations) depends on it: this order keeps every design byte-identical, where a
   * numeric one would give equivalent hardware in different files.
   */
  implicit val ordering: Ordering[OperandSource] = Ordering.by {
    case ReadPort(bank, port) => (0, bank.toString, port.toString)
    case Output(bank)         => (1, bank.toString, "")
    case Table                => (2, "", "")
  }
}

/**
 * The memory-storage schedule of a graph at the initiation interval of `base` (II >= 2): the same multiplier
 * units (classes, shapes, latencies) and CORDIC placements as `base`, adder units shared like the
 * multipliers, and every value written once into the bank of the unit that made it, in the cycle it is ready,
 * then read from there by address. Each bank has two read ports (two block-RAM copies): port 0 feeds units'
 * first operands, port 1 their second. The bit-accurate model does not depend on any of this.
 *
 * Timing (cycles of one sample, counted as in [[Schedule]]):
 *   - a value ready in cycle R leaves its unit in cycle R - 1 and is written into its bank `writeDelay`
 *     cycles later (registered on the way); a read's address may be presented from cycle R on, the array is
 *     read `arrayReadDelay` cycles after it, and the word is in a register `readLatency` cycles after the
 *     address;
 *   - a multiply or an addition reads its operands (address) `readLead` cycles before its issue: the read,
 *     then `forwardLead` clocks (the operand selected among its sources in `selectStages` registered stages,
 *     the last one in the fabric ahead of the unit; an addition's operands are aligned in the selection); a
 *     product is ready `base.mulLatency` cycles after the issue (the rounding shift and a capture register
 *     included), a sum one cycle after;
 *   - either takes a value off its unit's output register (no read) `forwardLead` cycles after it is ready,
 *     when that is its issue: the value's selection starts in the cycle it is there, then it goes the way a
 *     read word goes.
 * Each unit takes one operation and each read port one address per residue modulo II (two reads of the same
 * value in the same cycle share the port). A bank keeps `copies(b)` words per value, one per sample in
 * flight, picked by the sample's slot counter: a value is read before the sample `copies` later overwrites
 * it.
 */
final class BankedSchedule(val base: Schedule) {
  import Op._
  private val analysis = base.analysis
  private val graph = analysis.graph
  val clocksPerSample: Int = base.clocksPerSample
  private val ii = clocksPerSample

  private def isConst(x: NodeId) = graph(x).isInstanceOf[Const]

  /** The per-sample inputs, in the order the input stage writes them into their bank (one per clock). */
  val signals: IndexedSeq[Signal] = graph.signals.toIndexedSeq

  require(
    ii >= 2,
    "schedule.storage = memory shares units between clocks: it needs " +
      "schedule.clocks-per-sample >= 2 (at 1, use registers)"
  )
  require(
    signals.size <= ii,
    s"schedule.storage = memory writes the ${signals.size} per-sample inputs (velocities, accelerations, " +
      "payload) into a bank one " +
      s"per clock: it needs schedule.clocks-per-sample >= ${signals.size}, got $ii"
  )

  private val additions: IndexedSeq[NodeId] = graph.ids.filter(id =>
    graph(id) match {
      case _: Add | _: Sub | _: Neg => true
      case _                        => false
    }
  )

  /** Adder units: as asked, else the fewest that take every addition in the slots a unit offers. */
  val adderUnits: Int = {
    val fewest = math.max(1, base.unitsFor(additions.size, ii))
    base.request.adderUnits.foreach(a =>
      require(
        a >= fewest,
        s"schedule.adder-units = $a cannot take ${additions.size} additions in schedule.clocks-per-sample " +
          s"= $ii clocks; use adder-units >= $fewest (or auto)"
      )
    )
    base.request.adderUnits.getOrElse(fewest)
  }

  /** Banks: the inputs', then one per multiplier unit, per adder unit, and per CORDIC unit and function. */
  val banks: IndexedSeq[Bank] =
    (if (signals.nonEmpty) IndexedSeq(Bank.Inputs) else IndexedSeq.empty) ++
      (0 until base.multiplierUnits).map(Bank.Products) ++ (0 until adderUnits).map(Bank.Sums) ++
      (0 until base.cordicUnits).flatMap(u => Seq(Bank.Trig(u, TrigFn.Cos), Bank.Trig(u, TrigFn.Sin)))
  private val bankIndex: Map[Bank, Int] = banks.zipWithIndex.toMap

  /** Port assignments an operation may take on a unit: commutative operations either way round. */
  private def assignments(op: Op, unitShape: Option[MulShape]): Seq[IndexedSeq[Operand]] = {
    def operand(x: NodeId): Operand = if (isConst(x)) Operand.Constant(x) else Operand.Stored(x)
    def width(x: NodeId) = analysis(x).format.width
    op match {
      case Mul(a, b) =>
        val shape = unitShape.get
        Seq((a, b), (b, a)).distinct
          .filter { case (x, y) => width(x) <= shape.wide && width(y) <= shape.narrow }
          .map { case (x, y) => IndexedSeq(operand(x), operand(y)) }
      case Add(a, b) => Seq((a, b), (b, a)).distinct.map { case (x, y) => IndexedSeq(operand(x), operand(y)) }
      case Sub(a, b) => Seq(IndexedSeq(operand(a), operand(b)))
      case Neg(a)    => Seq(IndexedSeq(Operand.Zero, operand(a)))
      case other     => throw new IllegalStateException(s"BankedSchedule: $other runs on no shared unit")
    }
  }

  /**
   * What an operation runs on with `stages` select stages: its unit kind, units, read lead, result latency
   * and bank per unit.
   */
  private def kindOf(id: NodeId, stages: Int): Option[Kind] = {
    // A multiply or an addition takes its operand `stages` clocks after its selection starts (see
    // forwardLead).
    val lead = BankedSchedule.readLatency + stages
    graph(id) match {
      case _: Mul =>
        Some(
          Kind(
            UnitKind.Multiplier,
            base.unitsOf(id),
            lead,
            stages,
            u => Some(base.unitShape(u)),
            base.mulLatency(id),
            Bank.Products
          )
        )
      case _: Add | _: Sub | _: Neg =>
        Some(
          Kind(
            UnitKind.Adder,
            0 until adderUnits,
            lead,
            stages,
            _ => None,
            1,
            Bank.Sums
          )
        )
      case _ => None
    }
  }

  /**
   * Values whose producer is fixed before scheduling: inputs (one per clock) and sin/cos (the CORDIC
   * placements of `base`).
   */
  private val fixed: Map[Int, (Int, Bank)] = graph.ids.flatMap { id =>
    graph(id) match {
      case Input(signal) =>
        Some(
          id.index -> ((base.inputCycle + BankedSchedule.inputLatency + signals.indexOf(signal), Bank.Inputs))
        )
      case Trig(fn, angle) =>
        val slot = base.angleSlot(angle)
        Some(id.index -> ((slot.issue + base.trigLatency, Bank.Trig(slot.unit.get, fn))))
      case _ => None
    }
  }.toMap

  /**
   * Priority: the longest chain of leads and latencies from an operation to an output (the critical path
   * first).
   */
  private def heightOf(kinds: IndexedSeq[Option[Kind]]): IndexedSeq[Int] = {
    val users = graph.ids.flatMap(id => graph(id).operands.map(_.index -> id.index)).groupMap(_._1)(_._2)
    graph.ids.reverse
      .foldLeft(Map.empty[Int, Int]) { (h, id) =>
        val own = kinds(id.index).fold(0)(k => k.forwardLead + k.latency)
        h + (id.index -> (own + users.getOrElse(id.index, Nil).map(h).maxOption.getOrElse(0)))
      }
      .toSeq
      .sortBy(_._1)
      .map(_._2)
      .toIndexedSeq
  }

  /**
   * List scheduling in `order`: each operation at a cycle its operands can be read or forwarded by, on a unit
   * free at the cycle's residue with an operand order and bank read ports free at the residue of its read;
   * among those, the one adding the fewest inputs to the unit's operand multiplexers (most of a shared
   * datapath's logic).
   */
  private def scheduleWith(stages: Int, order: ListOrder, perturbation: Int = 0): BankedState = {
    val kinds = graph.ids.map(kindOf(_, stages))
    // A perturbed try raises each priority by 0 or 1 (seeded): an operation stays above its users,
    // which are at least a lead and a latency (>= 2) lower.
    val raise = new scala.util.Random(perturbation)
    val height = heightOf(kinds).map(h => if (perturbation == 0) h else h + raise.nextInt(2))
    val start = BankedState(
      ready = graph.ids.map(id => fixed.get(id.index).map(_._1)).toVector,
      bank = graph.ids.map(id => fixed.get(id.index).map(f => bankIndex(f._2))).toVector,
      placed = Vector.fill(graph.ops.size)(None),
      units = Set.empty,
      ports = Map.empty,
      reads = Vector.empty
    )
    val pending =
      graph.ids.filter(id => kinds(id.index).isDefined).sortBy(id => (-height(id.index), id.index))

    /**
     * `operands` of an operation of kind `k` issued in `t`: each stored one forwarded when it is ready
     * exactly `forwardLead` cycles before, else read from its bank; None when one is not available then or a
     * read port is taken.
     */
    def resolve(
        s: BankedState,
        operands: IndexedSeq[Operand],
        k: Kind,
        t: Int
    ): Seq[(IndexedSeq[Operand], Seq[BankRead])] = {
      // Per operand: the ways it can arrive at t (forwarded, or read on either bank port, its own position's
      // first).
      val ways: IndexedSeq[Seq[(Operand, Option[BankRead])]] = operands.zipWithIndex.map {
        case (Operand.Stored(x, _), position) =>
          val r = s.ready(x.index).get
          if (r + k.forwardLead == t) Seq((Operand.Forwarded(x), None))
          else if (r + k.lead <= t)
            Seq(position, 1 - position).map(port =>
              (Operand.Stored(x, port), Some(BankRead(x, s.bank(x.index).get, port, t - k.lead)))
            )
          else Nil
        case (other, _) => Seq((other, None))
      }
      def free(rs: Seq[BankRead]): Boolean = {
        val keyed = rs.map(r => readSlot(r) -> r)
        keyed.groupBy(_._1).forall(_._2.map(_._2).distinct.size == 1) && keyed.forall { case (key, use) =>
          s.ports.get(key).forall(_ == use)
        }
      }
      ways
        .foldLeft(Seq(IndexedSeq.empty[(Operand, Option[BankRead])]))((acc, w) =>
          for (a <- acc; x <- w) yield a :+ x
        )
        .map(choice => (choice.map(_._1), choice.flatMap(_._2)))
        .filter { case (_, rs) => free(rs) }
    }

    /** Whether every stored operand of `id` is ready by `t` (forwarded or read). */
    def candidate(s: BankedState, id: NodeId, t: Int): Boolean = {
      val k = kinds(id.index).get
      graph(id).operands
        .filterNot(isConst)
        .forall(x => s.ready(x.index).exists(r => r + k.forwardLead == t || r + k.lead <= t))
    }
    def sourceOf(s: BankedState, o: Operand): OperandSource = OperandSource.of(o, x => s.bank(x.index).get)
    def readSlot(r: BankRead) = ReadSlot(r.bank, r.port, r.cycle % ii)

    /**
     * Sources a placement adds to its unit's port multiplexers: each one is a multiplexer input as wide as
     * the unit.
     */
    def newSources(s: BankedState, kind: UnitKind, u: Int, operands: IndexedSeq[Operand]): Int =
      operands.indices.count(port =>
        !s.sources.getOrElse(UnitPort(kind, u, port), Set.empty).contains(sourceOf(s, operands(port)))
      )
    // Among the free units and operand orders, the one adding the fewest multiplexer inputs (then the first).
    def tryPlace(s: BankedState, id: NodeId, t: Int): Option[BankedState] = {
      val k = kinds(id.index).get
      val op = graph(id)
      val options = k.units.filterNot(u => s.units(UnitSlot(k.kind, u, t % ii))).flatMap { u =>
        assignments(op, k.shape(u)).flatMap(a => resolve(s, a, k, t).map { case (ops, rs) => (u, ops, rs) })
      }
      options.minByOption { case (u, a, _) => newSources(s, k.kind, u, a) }.map { case (u, a, rs) =>
        val placed = PlacedOp(id, k.kind, u, t, a, subtract = op.isInstanceOf[Sub] || op.isInstanceOf[Neg])
        s.copy(
          ready = s.ready.updated(id.index, Some(t + k.latency)),
          bank = s.bank.updated(id.index, Some(bankIndex(k.bank(u)))),
          placed = s.placed.updated(id.index, Some(placed)),
          units = s.units + UnitSlot(k.kind, u, t % ii),
          ports = s.ports ++ rs.map(r => readSlot(r) -> r),
          reads = s.reads ++ rs,
          sources = a.indices.foldLeft(s.sources) { (m, port) =>
            val key = UnitPort(k.kind, u, port)
            m.updated(key, m.getOrElse(key, Set.empty) + sourceOf(s, a(port)))
          }
        )
      }
    }
    def noFreePorts(clocks: Int, from: Int, what: String) = new IllegalArgumentException(
      s"schedule.storage = memory: for $clocks clocks from cycle $from no unit and bank " +
        s"read ports were free for $what; use a larger schedule.clocks-per-sample " +
        s"or schedule.storage = registers"
    )
    @scala.annotation.tailrec
    def byCycle(t: Int, s: BankedState, pending: IndexedSeq[NodeId], idle: Int): BankedState =
      if (pending.isEmpty) s
      else {
        val candidates = pending.filter(id => candidate(s, id, t))
        val (next, placed) = candidates.foldLeft((s, Set.empty[NodeId])) { case ((st, done), id) =>
          tryPlace(st, id, t).fold((st, done))(n => (n, done + id))
        }
        if (candidates.nonEmpty && placed.isEmpty && idle >= 2 * ii)
          throw noFreePorts(
            2 * ii,
            t - idle,
            s"${candidates.size} ready operations (node ${candidates.head.index}: ${graph(candidates.head)})"
          )
        byCycle(
          t + 1,
          next,
          pending.filterNot(placed),
          if (placed.isEmpty && candidates.nonEmpty) idle + 1 else 0
        )
      }
    def byHeight: BankedState = pending.foldLeft(start) { (s, id) =>
      val k = kinds(id.index).get
      val earliest = graph(id).operands
        .filterNot(isConst)
        .map(x => s.ready(x.index).get + k.forwardLead)
        .maxOption
        .getOrElse(0)
      // Every residue of the issue and of its reads comes up within lead + 2 II cycles.
      Iterator
        .range(earliest, earliest + k.lead + 2 * ii)
        .filter(t => candidate(s, id, t))
        .flatMap(t => tryPlace(s, id, t))
        .nextOption()
        .getOrElse(throw noFreePorts(k.lead + 2 * ii, earliest, s"node ${id.index} (${graph(id)})"))
    }
    order match {
      case ListOrder.ByCycle  => byCycle(0, start, pending, 0)
      case ListOrder.ByHeight => byHeight
    }
  }

  /** Cycle at which every output of a scheduled state is in its register. */
  private def outputsReadyIn(s: BankedState): Int =
    graph.outputs.flatMap(o => s.ready(o.node.index)).maxOption.getOrElse(base.inputCycle)

  /** A scheduled state's latency: the output stage reads the outputs when all are ready. */
  private def latencyOf(s: BankedState): Int = outputsReadyIn(s) + BankedSchedule.outputStages

  /**
   * Clocks a unit port's operand takes to be selected among its sources ([[BankedSchedule.selectStages]], or
   * one where the list scheduler then finds no free unit and read ports for some operation: a tight interval,
   * where the longer leads move the residues the reads need), and the list order: the one asked for, or of
   * the orders that schedule every operation, the one with the least latency.
   */
  private val (chosen, orderLatencies) = {
    def schedules(stages: Int): Seq[(ListOrder, Either[IllegalArgumentException, BankedState])] =
      base.request.listOrder.fold(ListOrder.all)(Seq(_)).map { order =>
        val perturbations = if (order == ListOrder.ByHeight) 0 until base.request.listTries else Seq(0)
        val tries = perturbations.map(k =>
          try Right(scheduleWith(stages, order, k))
          catch { case e: IllegalArgumentException => Left(e) }
        )
        order -> tries
          .collect { case Right(s) => s }
          .minByOption(latencyOf)
          .toRight(tries.head.swap.toOption.get)
      }
    val full = schedules(BankedSchedule.selectStages)
    val (stages, tried) =
      if (full.exists(_._2.isRight)) (BankedSchedule.selectStages, full) else (1, schedules(1))
    val best = tried
      .collect { case (order, Right(s)) => (stages, order, s) }
      .minByOption(c => latencyOf(c._3))
      .getOrElse(throw tried.flatMap(_._2.left.toOption).last)
    (best, tried.map { case (order, r) => order -> r.toOption.map(latencyOf) })
  }
  val selectStages: Int = chosen._1

  /**
   * The list order that gave the schedule: the one asked for, or of the orders that place every operation,
   * the one with the least latency.
   */
  val listOrder: ListOrder = chosen._2

  /**
   * Latency each list order tried gave (None: it found no free unit and ports for some operation), for
   * reports.
   */
  val latencyByOrder: Seq[(ListOrder, Option[Int])] = orderLatencies
  private val state: BankedState = chosen._3

  /**
   * Cycles from the start of a value's selection (`selectStages` clocks) to the issue of the multiply or
   * addition that takes it off its unit's output register: a multiplier's operand is then registered in the
   * fabric, ahead of the multiplier's own input registers, so the selection's routing to the multiplier
   * blocks gets a clock of its own; an addition's operand, aligned in the selection's first stage (wiring)
   * and inverted for a subtraction in its last, is registered beside the carry in, so the carry chain has a
   * clock of its own.
   */
  val forwardLead: Int = selectStages

  /**
   * Cycles from a read's address to the issue of the multiply or addition that reads it: the read, then as a
   * forwarded value.
   */
  val readLead: Int = BankedSchedule.readLatency + forwardLead

  private val height: IndexedSeq[Int] = heightOf(graph.ids.map(kindOf(_, selectStages)))

  /** The latency dependences alone would allow (unlimited units and ports), for reports. */
  val dependenceBound: Int = graph.ids.map { id =>
    (graph(id) match {
      case Input(_) | Trig(_, _) => fixed(id.index)._1
      case _                     => 0
    }) + height(id.index)
  }.max + BankedSchedule.outputStages

  /**
   * Cycle in which each node's value is in its unit's output register and written into its bank (None: a
   * constant).
   */
  def ready(id: NodeId): Option[Int] = state.ready(id.index)

  /** Each stored node's bank. */
  def bankOf(id: NodeId): Option[Int] = state.bank(id.index)

  /** Multiplies and additions with their units, issues and operand ports. */
  val ops: IndexedSeq[PlacedOp] = state.placed.flatten

  /** The operations on unit `unit` of `kind`, in the schedule's order. */
  def opsOn(kind: UnitKind, unit: Int): IndexedSeq[PlacedOp] =
    ops.filter(o => o.kind == kind && o.unit == unit)

  /** Every bank read. */
  val reads: IndexedSeq[BankRead] = state.reads

  /** Cycle at which every output is in its register: the output stage reads them then. */
  val outputsReady: Int = outputsReadyIn(state)

  /** Cycles from a sample on the input port to its torques on the output port (output stage included). */
  val latency: Int = latencyOf(state)

  /**
   * Values of each bank that some operation reads from it, in the order they are ready: a value's slot is its
   * place here.
   */
  val values: IndexedSeq[IndexedSeq[NodeId]] = {
    val read = reads.map(_.node).toSet
    val byBank = graph.ids.filter(read).groupBy(id => bankOf(id).get)
    banks.indices.map(b => byBank.getOrElse(b, IndexedSeq.empty).sortBy(id => (ready(id).get, id.index)))
  }
  private val slotOf: Map[NodeId, Int] = values.flatMap(_.zipWithIndex).toMap
  def slot(id: NodeId): Int = slotOf(id)

  /**
   * Words per value in each bank: one per sample in flight between a value's write and its last read, rounded
   * up to a power of 2.
   */
  val copies: IndexedSeq[Int] = {
    val lastArrayRead = reads.groupMapReduce(_.node)(_.cycle + BankedSchedule.arrayReadDelay)(math.max)
    // Sample s + copies writes a value in cycle copies * II + ready - 1 + writeDelay, which must come
    // strictly after the last
    // cycle the array is read for sample s: the hardware leaves a read undefined when its word is written in
    // the same cycle.
    def written(v: NodeId) = ready(v).get - 1 + BankedSchedule.writeDelay
    values.map(vs =>
      BankedSchedule.pow2(
        vs.map(v => lastArrayRead.get(v).fold(1)(l => (l - written(v)) / ii + 1)).maxOption.getOrElse(1)
      )
    )
  }

  /** Samples in flight at most: the slot counter counts modulo this (every bank's copies divide it). */
  val slotCount: Int = copies.maxOption.getOrElse(1)

  /**
   * Cycles of a sample in which `cycle` lies, counted in whole intervals: what a slot counter has advanced by
   * then.
   */
  def intervalsBefore(cycle: Int): Int = cycle / ii

  /** Adder unit widths: every operand aligned to the result's fraction bits, and every result, fit. */
  val adderWidths: IndexedSeq[Int] = (0 until adderUnits).map { u =>
    opsOn(UnitKind.Adder, u)
      .flatMap { o =>
        val f = analysis(o.node).format
        f.width +: graph(o.node).operands.map(x =>
          analysis(x).format.width + f.fracBits - analysis(x).format.fracBits
        )
      }
      .maxOption
      .getOrElse(2)
  }

  /** Where each multiply's product is rounded, and its operands' shifts that bring it there. */
  lazy val alignment: ProductAlignment = new ProductAlignment(this)

  /** Word width of each bank: its widest value. */
  val bankWidths: IndexedSeq[Int] =
    values.map(vs => vs.map(v => analysis(v).format.width).maxOption.getOrElse(1))

  /** Result width of each bank's unit: the widest value it makes (written, forwarded or an output). */
  val unitWidths: IndexedSeq[Int] = {
    val made = graph.ids
      .filter(id => bankOf(id).isDefined)
      .groupMapReduce(id => bankOf(id).get)(id => analysis(id).format.width)(math.max)
    banks.indices.map(bank => made.getOrElse(bank, 1))
  }

  /** Result width of `bank`'s unit ([[unitWidths]]). */
  def unitWidth(bank: Bank): Int = unitWidths(banks.indexOf(bank))

  /** Block-RAM bits of the banks (two copies each, for the two read ports), for reports. */
  def memoryBits: Long =
    banks.indices.map(b => 2L * bankWidths(b) * copies(b) * BankedSchedule.pow2(values(b).size)).sum
}

object BankedSchedule {

  /**
   * Cycles from a bank read's address to its word in the fabric register the unit ports select from: the
   * block RAM's address and output registers, then two in the fabric, so the route from the block RAM (which
   * may sit far from the units that read it) has a clock of its own with no logic in it. One last register,
   * not a copy per unit port: synthesis merges such copies back into one.
   */
  val readLatency: Int = 4

  /** Cycles from a bank read's address to the cycle its array is read: the block RAM's address register. */
  val arrayReadDelay: Int = 1

  /**
   * Cycles from a unit's result to its bank's write: one register (data, address and enable), so the route
   * from a unit to its block RAM's write port gets a clock of its own. The array then holds a value from the
   * cycle after it is ready, the earliest a read (its address presented when the value is ready, the array
   * read [[arrayReadDelay]] later) looks at it.
   */
  val writeDelay: Int = 1
  require(
    writeDelay <= arrayReadDelay,
    "BankedSchedule: a value's first read would look at the array before its write"
  )

  /**
   * Registers of the output stage, after every output is ready: the saturation compares (beside the rounding
   * adder), then the bound multiplexer into the port's torque register and the OR of every torque's compares
   * into one register, then each joint's flag. With two stages, the compares would share a clock with the
   * multiplexer, or the OR with the flags, and either path would limit the clock memory storage reaches.
   */
  val outputStages: Int = 3

  /**
   * Clocks a unit port's operand takes to be selected among its sources, where the schedule allows (a unit
   * may have 30 sources a port).
   */
  val selectStages: Int = 2

  /**
   * Places ahead of the inputs in their chain (loaded in the input cycle, the one cycle the clamped values
   * are in their registers): a sample's first bank write must come after the microcode table's first word
   * (read [[reducerload.arm.Microcode.ahead]] cycles ahead).
   */
  val inputLoadDelay: Int = 1

  /**
   * Signal k of the input stage is ready in cycle `inputCycle + inputLatency + k`: all are loaded into a
   * chain of registers in the input cycle, behind `inputLoadDelay` places, and the chain's head is written
   * one per clock.
   */
  val inputLatency: Int = inputLoadDelay + 2

  /** The least power of 2 at or above `n` (at least 1). */
  def pow2(n: Int): Int = if (n <= 1) 1 else Integer.highestOneBit(n - 1) << 1
}
