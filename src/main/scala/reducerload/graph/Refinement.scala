package reducerload.graph

/**
 * What the refinement may move in one node of a registers-storage modulo schedule. Operands are node indices
 * of the same problem; a constant operand is a [[RefineNode.Literal]] node.
 */
sealed trait RefineNode {
  def operands: IndexedSeq[Int]

  /** Bits of the node's value (its registers, an operand multiplexer's input). */
  def width: Int
}
object RefineNode {

  /** A constant: a literal input of the multiplexers that read it, no register. */
  final case class Literal(width: Int) extends RefineNode { def operands: IndexedSeq[Int] = IndexedSeq.empty }

  /** A value whose cycle the refinement does not move (an input, a sin/cos): ready in cycle `ready`. */
  final case class Fixed(ready: Int, width: Int) extends RefineNode {
    def operands: IndexedSeq[Int] = IndexedSeq.empty
  }

  /**
   * An operation on an operator of its own (an addition, a shift-and-add multiply): issued in any cycle its
   * operands allow, its value ready `latency` cycles later. `forwardable` as for [[Shared]] (a shift-and-add
   * product's one reader may take it off its adder tree); `takesForwarded`: it may take a forwardable operand
   * off its operator's output (an addition may, a shift-and-add multiply's adder tree may not).
   */
  final case class Own(
      operands: IndexedSeq[Int],
      latency: Int,
      width: Int,
      forwardable: Boolean = false,
      takesForwarded: Boolean = true
  ) extends RefineNode

  /**
   * A multiply on a shared unit of `units`, at most one per unit and residue: `operands` in the order of its
   * unit's ports ([[MulShape.widths]]), which it may swap when `swappable` (each fits the other's port). Its
   * value is captured `latency` cycles after its issue, unless `forwardable` and its one reader, an [[Own]]
   * operation, takes it off the unit's output the cycle before. A `chained` one (a product of an
   * [[Accumulation]], whose tree's sums are [[Fixed]]) leaves its unit in a residue of its own among its
   * chain's, all within an interval, and is ready [[Accumulation.rootDelay]] before its root. A `memory` one
   * (`schedule.product-memories`: a truncated product) takes no register when every read lies in its
   * [[ProductMemory]]'s window, one read per residue on its unit's read port.
   */
  final case class Shared(
      operands: IndexedSeq[Int],
      latency: Int,
      width: Int,
      units: Range,
      swappable: Boolean,
      forwardable: Boolean,
      chained: Option[Chained] = None,
      memory: Boolean = false
  ) extends RefineNode {
    require(operands.size == 2, s"RefineNode.Shared: ${operands.size} operands, a multiply has 2")
  }
}

/**
 * A multiply of the chain summed into node `root` (an accumulated tree's products: one accumulator takes them
 * off their units, so each in a residue of its own, all within an interval), a [[RefineNode.Fixed]] node
 * whose cycle is at least [[Accumulation.rootDelay]] after the chain's last product is ready. The
 * accumulator's input selects among the chain's units: `width` bits per unit beyond the first, counted as
 * multiplexer input bits.
 */
final case class Chained(root: Int, width: Int)

/**
 * A solution of a [[RefinementProblem]]: each node's issue cycle (fixed nodes and literals: -1), each shared
 * node's unit (else -1) and whether its operands are swapped on the unit's ports.
 */
final case class Refined(issue: IndexedSeq[Int], unit: IndexedSeq[Int], swapped: IndexedSeq[Boolean])

/**
 * The registers-storage schedule as a problem to improve (CIRCT's split: the problem here, the list scheduler
 * and this annealing its algorithms): every value is held in registers written once per sample, one more per
 * interval its last reader needs it, and each unit port multiplexes the distinct (value, register) pairs its
 * operations read; long stretches wait in block RAM instead ([[HeldTaps]]). The cost is what those take in
 * logic elements: operand-multiplexer input bits beyond the first of each port (weight `muxWeight`), held
 * register bits, the first register of each value included unless it is forwarded or read from its unit's
 * product memory (weight `heldWeight`), block-RAM delays (weight `tapWeight` each), and the product memories'
 * read-port conflicts (each a mean product's register) and members alone on their unit (no memory for one:
 * their registers); [[LogicCost]] gives the LE prediction's. With product memories the refinement so moves
 * reads into the memories' windows and apart on their ports (docs/timing-closure.md).
 *
 * @param interval
 *   clocks per sample (II >= 2)
 * @param outputs
 *   the nodes the output stage reads when every output is ready
 * @param outputsBy
 *   the cycle every output must be ready by (the list schedule's: refinement never lengthens the latency)
 * @param portWidths
 *   each unit's port widths
 * @param memoryMinCycles
 *   `datapath.memory-delay-min-cycles`: a value read that many clocks or more after its first register is
 *   read from a block-RAM delay ([[HeldTaps]]; 0: never)
 */
final case class RefinementProblem(
    interval: Int,
    nodes: IndexedSeq[RefineNode],
    outputs: Seq[Int],
    outputsBy: Int,
    portWidths: Int => IndexedSeq[Int],
    muxWeight: Double,
    heldWeight: Double,
    memoryMinCycles: Int = 0,
    tapWeight: Double = 0.0
) {
  import RefineNode._
  require(interval >= 2, s"RefinementProblem: interval $interval; at 1 every operation has its own operator")
  nodes.zipWithIndex.foreach { case (n, i) =>
    require(n.operands.forall(_ < i), s"RefinementProblem: node $i reads a later node")
    n match {
      case Shared(_, _, _, _, _, _, Some(c), _) =>
        require(
          nodes.lift(c.root).exists(_.isInstanceOf[Fixed]),
          s"RefinementProblem: node $i chained to node ${c.root}, not a fixed node"
        )
      case _ =>
    }
  }

  /** Each accumulated root's chain: the chained multiplies summed into it, by the root's node. */
  val chains: Map[Int, IndexedSeq[Int]] =
    nodes.indices
      .flatMap(i => nodes(i) match { case s: Shared => s.chained.map(c => c.root -> i); case _ => None })
      .groupMap(_._1)(_._2)

  /** The cycle a chained multiply must be ready by: its root's, less [[Accumulation.rootDelay]]. */
  private def readyBy(c: Chained): Int = nodes(c.root).asInstanceOf[Fixed].ready - Accumulation.rootDelay

  /**
   * The problem with the accumulated roots ready in the cycles `rootReady` gives (the others as they are) and
   * every output by `by`: where the solver moved a chain's products.
   */
  def withRoots(rootReady: Map[Int, Int], by: Int): RefinementProblem =
    copy(
      nodes = nodes.indices.map(i =>
        rootReady.get(i).fold(nodes(i))(r => nodes(i).asInstanceOf[Fixed].copy(ready = r))
      ),
      outputsBy = by
    )

  private val n = nodes.size
  private val users: Array[Array[Int]] = {
    val us = Array.fill(n)(List.empty[Int])
    for (i <- (0 until n).reverse; x <- nodes(i).operands.distinct) us(x) ::= i
    us.map(_.toArray)
  }
  private val isOutput: Array[Boolean] = Array.tabulate(n)(i => outputs.contains(i))
  private val isLiteral: Array[Boolean] = nodes.map(_.isInstanceOf[Literal]).toArray

  /** The cycle a node's value is ready under `issue`. */
  private def readyOf(i: Int, issue: Int => Int): Int = nodes(i) match {
    case Fixed(r, _)        => r
    case Own(_, l, _, _, _) => issue(i) + l
    case s: Shared          => issue(i) + s.latency
    case Literal(_)         => Int.MinValue
  }

  private def forwardable(i: Int): Boolean = nodes(i) match {
    case s: Shared => s.forwardable
    case o: Own    => o.forwardable
    case _         => false
  }

  /** Whether a product's one reader takes it off its operator's output (no register of its own). */
  private def forwarded(i: Int, issue: Int => Int): Boolean =
    forwardable(i) && users(i).length == 1 && {
      val reader = users(i).head
      takesForwarded(reader) && issue(reader) == readyOf(i, issue) - 1
    }

  private def takesForwarded(reader: Int): Boolean = nodes(reader) match {
    case o: Own => o.takesForwarded
    case _      => false
  }

  /**
   * The earliest cycle node `reader` may read `x`: when it is ready, or a cycle before off a unit's output.
   */
  private def available(x: Int, reader: Int, issue: Int => Int): Int = nodes(x) match {
    case Literal(_)                                    => Int.MinValue
    case _ if forwardable(x) && takesForwarded(reader) => readyOf(x, issue) - 1
    case _                                             => readyOf(x, issue)
  }

  /** Every rule a solution must keep: dependences, one operation per unit and residue, the outputs' cycle. */
  def check(r: Refined): Unit = {
    def issue(i: Int) = r.issue(i)
    nodes.indices.foreach { i =>
      nodes(i) match {
        case _: Own | _: Shared =>
          nodes(i).operands.foreach(x =>
            require(
              issue(i) >= available(x, i, issue),
              s"RefinementProblem: node $i issues in ${issue(i)} before its operand $x is available"
            )
          )
        case _ =>
      }
      nodes(i) match {
        case s: Shared =>
          require(s.units.contains(r.unit(i)), s"RefinementProblem: node $i on unit ${r.unit(i)}")
          s.chained.foreach(c =>
            require(
              r.issue(i) + s.latency <= readyBy(c),
              s"RefinementProblem: node $i of chain ${c.root} ready after ${readyBy(c)}, its root's less " +
                Accumulation.rootDelay
            )
          )
        case _ =>
      }
    }
    chains.foreach { case (c, members) =>
      val ready = members.map(i => r.issue(i) + nodes(i).asInstanceOf[Shared].latency)
      require(
        ready.map(Math.floorMod(_, interval)).distinct.size == members.size,
        s"RefinementProblem: the chain into node $c has two products ready in one residue"
      )
      require(
        ready.max - ready.min < interval,
        s"RefinementProblem: the chain into node $c is ready over more than an interval"
      )
    }
    val shared = nodes.indices.filter(nodes(_).isInstanceOf[Shared])
    shared.groupBy(i => (r.unit(i), Math.floorMod(r.issue(i), interval))).foreach { case ((u, res), on) =>
      require(on.size == 1, s"RefinementProblem: nodes ${on.mkString(", ")} share unit $u in residue $res")
    }
    outputs.foreach(o =>
      require(
        isLiteral(o) || readyOf(o, issue) <= outputsBy,
        s"RefinementProblem: output $o ready after $outputsBy"
      )
    )
  }

  /** [[cost]]'s parts: operand-multiplexer input bits, held register bits and block-RAM delays. */
  def bits(r: Refined): (Long, Long, Int) = {
    def issue(i: Int) = r.issue(i)
    val sources = scala.collection.mutable.Map.empty[(Int, Int), Set[Long]].withDefaultValue(Set.empty)
    nodes.indices.foreach { i =>
      nodes(i) match {
        case s: Shared =>
          val ports = if (r.swapped(i)) s.operands.reverse else s.operands
          ports.zipWithIndex.foreach { case (x, k) =>
            sources((r.unit(i), k)) += sourceKey(x, r.issue(i), issue)
          }
        case _ =>
      }
    }
    // each chain's accumulator: its width per unit beyond the first
    val accumulatorInputs = chains.values.map { members =>
      val width = nodes(members.head).asInstanceOf[Shared].chained.get.width
      (members.map(r.unit).distinct.size - 1).toLong * width
    }.sum
    val mux = sources.map { case ((u, k), set) =>
      (set.size - 1).toLong * portWidths(u)(k)
    }.sum + accumulatorInputs
    val held = nodes.indices.map(i => heldBits(i, issue, forwarded(i, issue)))
    (mux, held.map(_._1).sum, held.map(_._2).sum)
  }

  /**
   * What the refinement minimises: the predicted logic elements of a solution's multiplexers and registers.
   */
  def cost(r: Refined): Double = {
    val (mux, held, taps) = bits(r)
    muxWeight * mux + heldWeight * held + tapWeight * taps + conflictWeight * memoryConflicts(r) +
      heldWeight * loneMemberBits(r)
  }

  /** Products in memory each on a unit, by unit. */
  private def memoryMembers(r: Refined): Map[Int, Seq[Int]] = {
    def issue(i: Int) = r.issue(i)
    nodes.indices.filter(i => inMemory(i, issue)).groupBy(r.unit)
  }

  /**
   * Bits of products in memory alone on their unit: [[ProductMemory.allocate]] builds no memory for one
   * member, so each keeps its register.
   */
  def loneMemberBits(r: Refined): Long =
    memoryMembers(r).values.collect { case Seq(i) => nodes(i).width.toLong }.sum

  /**
   * Reads of products in memory beyond the first in one residue of one unit's read port: each leaves a
   * product out of its memory ([[ProductMemory.allocate]]), in a register after all.
   */
  def memoryConflicts(r: Refined): Int = {
    def issue(i: Int) = r.issue(i)
    val reads = memoryMembers(r).values.flatten.toSeq.flatMap { i =>
      readCycles(i, issue).map(t => (r.unit(i), Math.floorMod(t, interval))).distinct
    }
    reads.groupBy(identity).values.map(_.size - 1).sum
  }

  /** A read-port conflict's weight: the register a product left out of its memory takes (a mean one's). */
  private val conflictWeight: Double = {
    val ws = nodes.collect { case s: Shared if s.memory => s.width }
    if (ws.isEmpty) 0.0 else heldWeight * ws.sum / ws.size
  }

  /** What a port reads for operand `x` in cycle `t`: the value's register of that interval, or a literal. */
  private def sourceKey(x: Int, t: Int, issue: Int => Int): Long =
    if (isLiteral(x)) -1L - x else x.toLong * RefinementProblem.stageSpan + (t - readyOf(x, issue)) / interval

  /**
   * Whether a product is read from its unit's product memory: a `memory` one whose every read lies in
   * [[ProductMemory.Candidate.storable]]'s window (a read beyond one in a residue of the unit's port is a
   * conflict, see [[memoryConflicts]]).
   */
  private def inMemory(i: Int, issue: Int => Int): Boolean = nodes(i) match {
    case s: Shared if s.memory =>
      readCycles(i, issue).forall(ProductMemory.inWindow(readyOf(i, issue), _, interval))
    case _ => false
  }

  /** The cycles a node is read in: by its users at their issue, an output by the output stage. */
  private def readCycles(i: Int, issue: Int => Int): Seq[Int] =
    users(i).toSeq.map(issue) ++ (if (isOutput(i)) Seq(outputsBy) else Nil)

  /** The last cycle a node is read: by its users at their issue, an output by the output stage. */
  private def lastRead(i: Int, issue: Int => Int): Int = {
    val byUsers = users(i).foldLeft(Int.MinValue)((m, u) => math.max(m, issue(u)))
    if (isOutput(i)) math.max(byUsers, outputsBy) else byUsers
  }

  /**
   * Register bits holding node `i`: one register per interval from its ready cycle to its last read, none
   * when forwarded.
   */
  private def heldBits(i: Int, issue: Int => Int, isForwarded: Boolean): (Long, Int) =
    nodes(i) match {
      case Literal(_)                                                => (0L, 0)
      case node if (users(i).isEmpty && !isOutput(i)) || isForwarded => (0L, 0)
      case node if inMemory(i, issue)                                => (0L, 0)
      case node =>
        val taps = HeldTaps(interval, readyOf(i, issue), readCycles(i, issue), memoryMinCycles)
        (taps.registerBits(node.width), taps.delayed.size)
    }

  /**
   * `start` improved by seeded simulated annealing (the same result every run), never worse than `start`:
   * `steps` moves, each either a multiply traded to another unit of its class in its residue (with the
   * operation there, if any), its operands swapped on their ports, or a node issued in another cycle its
   * operands and readers allow (a multiply onto a unit free in the new residue, its current one first), kept
   * when it lowers the cost or, less and less often, when it raises it. Arrays and no allocation per step:
   * the UR5 at 17 clocks per sample takes millions of steps.
   */
  def anneal(start: Refined, steps: Long, seed: Long): Refined = {
    check(start)
    new Annealing(start, seed).run(steps)
  }

  /** The annealing's state, updated in place move by move. */
  private final class Annealing(start: Refined, seed: Long) {
    private val issue = start.issue.toArray
    private val unit = start.unit.toArray
    private val swapped = start.swapped.toArray
    // per node: 0 literal, 1 fixed, 2 own, 3 shared
    private val kind = nodes.map {
      case _: Literal => 0
      case _: Fixed   => 1
      case _: Own     => 2
      case _: Shared  => 3
    }.toArray
    private val latency = nodes.map {
      case Own(_, l, _, _, _) => l
      case s: Shared          => s.latency
      case _                  => 0
    }.toArray
    private val fixedReady = nodes.map { case Fixed(r, _) => r; case _ => 0 }.toArray
    private val width = nodes.map(_.width).toArray
    private val operands = nodes.map(_.operands.toArray).toArray
    private val canForward = nodes.indices.map(forwardable).toArray
    private val canTake = nodes.indices.map(takesForwarded).toArray
    private val swappable = nodes.map { case s: Shared => s.swappable; case _ => false }.toArray
    private val memory = nodes.map { case s: Shared => s.memory; case _ => false }.toArray
    private def inMemory(i: Int): Boolean = memory(i) && {
      val r = ready(i)
      val us = users(i)
      var ok = !isOutput(i) || ProductMemory.inWindow(r, outputsBy, interval)
      var k = 0
      while (ok && k < us.length) { ok = ProductMemory.inWindow(r, issue(us(k)), interval); k += 1 }
      ok
    }
    // each chained multiply's chain (its members, itself included); unchained: empty
    private val chain: Array[Array[Int]] = nodes.map {
      case s: Shared => s.chained.fold(Array.empty[Int])(c => chains(c.root).toArray)
      case _         => Array.empty[Int]
    }.toArray
    private def chained(i: Int) = chain(i).nonEmpty
    private val chainedBy = nodes.map { case s: Shared => s.chained.fold(0)(readyBy); case _ => 0 }.toArray
    private val chainWidth = nodes.map { case s: Shared => s.chained.fold(0)(_.width); case _ => 0 }.toArray

    /** Input bits of the accumulator of node `i`'s chain beyond its first unit's (none unchained). */
    private def accumulatorBits(i: Int): Long =
      if (!chained(i)) 0L
      else {
        val members = chain(i)
        var distinct = 0
        var k = 0
        while (k < members.length) {
          var m = 0
          while (m < k && unit(members(m)) != unit(members(k))) m += 1
          if (m == k) distinct += 1
          k += 1
        }
        (distinct - 1).toLong * chainWidth(i)
      }
    private val classUnits = nodes.map {
      case s: Shared => s.units.toArray; case _ => Array.empty[Int]
    }.toArray
    private val sharedReaders = users.map(_.filter(kind(_) == 3))
    private val unitCount = classUnits.foldLeft(0)((m, us) => us.foldLeft(m)((mm, u) => math.max(mm, u + 1)))
    private val widths = Array.tabulate(unitCount)(u => portWidths(u).toArray)
    // the operation on each (unit, residue), and how many of each unit port's operations read each source
    private val occupant = Array.fill(unitCount, interval)(-1)
    private val counts = Array.fill(unitCount, 2)(new java.util.HashMap[Long, Integer]())
    private val rng = new scala.util.Random(seed)

    private def residue(t: Int) = Math.floorMod(t, interval)
    private def ready(i: Int): Int = if (kind(i) == 1) fixedReady(i) else issue(i) + latency(i)
    private def availableTo(x: Int, reader: Int): Int =
      if (canForward(x) && canTake(reader)) ready(x) - 1 else ready(x)
    private def isForwarded(i: Int): Boolean =
      canForward(i) && users(i).length == 1 && {
        val r = users(i)(0)
        canTake(r) && issue(r) == ready(i) - 1
      }
    private def key(x: Int, t: Int): Long =
      if (kind(x) == 0) -1L - x else x.toLong * RefinementProblem.stageSpan + (t - ready(x)) / interval
    private def portOperand(i: Int, k: Int): Int = operands(i)(if (swapped(i)) 1 - k else k)
    private def enter(i: Int, sign: Int): Unit = {
      var k = 0
      while (k < 2) {
        val m = counts(unit(i))(k)
        val kk = key(portOperand(i, k), issue(i))
        val c = m.getOrDefault(kk, 0) + sign
        if (c == 0) m.remove(kk) else m.put(kk, c)
        k += 1
      }
    }
    private def muxBits(u: Int): Long =
      math.max(0, counts(u)(0).size - 1).toLong * widths(u)(0) + math
        .max(0, counts(u)(1).size - 1)
        .toLong * widths(u)(1)
    // the first stage read from block RAM (HeldTaps: k intervals of memoryMinCycles clocks or more)
    private val memoryStage =
      if (memoryMinCycles == 0) Int.MaxValue else math.max(1, (memoryMinCycles + interval - 1) / interval)
    private val tapStages = new Array[Boolean](math.max(0, outputsBy) / interval + 2)

    /** The logic elements of a value's registers and block-RAM taps ([[HeldTaps]], without allocating). */
    private def held(i: Int): Double =
      if (kind(i) == 0 || (users(i).isEmpty && !isOutput(i)) || isForwarded(i)) 0.0
      else if (inMemory(i)) 0.0
      else {
        val r = ready(i)
        val us = users(i)
        var chain = 0
        var taps = 0
        def stage(t: Int) = (t - r) / interval
        def read(t: Int): Unit = {
          val k = stage(t)
          if (k < memoryStage) chain = math.max(chain, k)
          else if (!tapStages(k)) { tapStages(k) = true; taps += 1 }
        }
        def unmark(t: Int): Unit = if (stage(t) >= memoryStage) tapStages(stage(t)) = false
        if (isOutput(i)) read(outputsBy)
        var k = 0
        while (k < us.length) { read(issue(us(k))); k += 1 }
        if (isOutput(i)) unmark(outputsBy)
        k = 0
        while (k < us.length) { unmark(issue(us(k))); k += 1 }
        heldWeight * (chain + 1).toLong * width(i) + tapWeight * taps
      }

    private def rebind(i: Int, to: Int): Unit = {
      val from = unit(i)
      val r = residue(issue(i))
      val other = occupant(to)(r)
      enter(i, -1)
      if (other >= 0) enter(other, -1)
      unit(i) = to
      occupant(to)(r) = i
      occupant(from)(r) = other
      if (other >= 0) { unit(other) = from; enter(other, 1) }
      enter(i, 1)
      refresh(i)
      if (other >= 0) refresh(other)
    }
    private def swapPorts(i: Int): Unit = { enter(i, -1); swapped(i) = !swapped(i); enter(i, 1) }

    /** Node `i` issued in `t` (a shared one on unit `u`), the multiplies reading it re-entered. */
    private def retime(i: Int, t: Int, u: Int): Unit = {
      val rs = sharedReaders(i)
      if (kind(i) == 3) { enter(i, -1); occupant(unit(i))(residue(issue(i))) = -1 }
      var k = 0
      while (k < rs.length) { enter(rs(k), -1); k += 1 }
      issue(i) = t
      if (kind(i) == 3) { unit(i) = u; occupant(u)(residue(t)) = i; enter(i, 1) }
      k = 0
      while (k < rs.length) { enter(rs(k), 1); k += 1 }
      refresh(i)
      val os = operands(i)
      k = 0
      while (k < os.length) { refresh(os(k)); k += 1 }
    }

    /**
     * The cost of the units node `i` (on unit `u`, or -1) and its readers use, and of its and its operands'
     * registers.
     */
    private def local(i: Int, u: Int): Double = {
      // units: distinct among the readers', i's and u
      val rs = sharedReaders(i)
      var mux = 0L
      val seen = new java.util.BitSet(unitCount)
      def add(v: Int): Unit = if (v >= 0 && !seen.get(v)) { seen.set(v); mux += muxBits(v) }
      if (kind(i) == 3) add(unit(i))
      add(u)
      var k = 0
      while (k < rs.length) { add(unit(rs(k))); k += 1 }
      var h = held(i)
      val os = operands(i)
      k = 0
      while (k < os.length) {
        // an operand read twice (x * x) counts once
        if (k == 0 || os(k) != os(0)) h += held(os(k))
        k += 1
      }
      muxWeight * (mux + accumulatorBits(i)) + h
    }

    (0 until n).foreach(i => if (kind(i) == 3) { occupant(unit(i))(residue(issue(i))) = i; enter(i, 1) })

    // each unit's memory read port: the reads of products in memory in each residue, the reads beyond one
    // over all ports, and each product's unit and residues as counted (-1: not in memory); each unit's
    // members and their bits, and the bits of members alone on their unit (loneMemberBits)
    private val memUse = Array.fill(unitCount, interval)(0)
    private var memConflicts = 0L
    private val memMembers = new Array[Int](unitCount)
    private val memBits = new Array[Long](unitCount)
    private var memLoneBits = 0L
    private def lone(u: Int): Long = if (memMembers(u) == 1) memBits(u) else 0L
    private def join(u: Int, i: Int, sign: Int): Unit = {
      val before = lone(u)
      memMembers(u) += sign; memBits(u) += sign * width(i)
      memLoneBits += lone(u) - before
    }
    private def memPenalty: Double = conflictWeight * memConflicts + heldWeight * memLoneBits
    private val memUnit = Array.fill(n)(-1)
    private val memCount = new Array[Int](n)
    private val memRes: Array[Array[Int]] = Array.tabulate(n)(i => new Array[Int](users(i).length + 1))
    private def unregister(i: Int): Unit = if (memUnit(i) >= 0) {
      val u = memUnit(i)
      var k = 0
      while (k < memCount(i)) {
        val r = memRes(i)(k); val c = memUse(u)(r)
        if (c >= 2) memConflicts -= 1
        memUse(u)(r) = c - 1; k += 1
      }
      join(u, i, -1)
      memUnit(i) = -1; memCount(i) = 0
    }
    private def addRead(i: Int, u: Int, t: Int): Unit = {
      val r = residue(t)
      var k = 0
      var dup = false
      while (k < memCount(i)) { if (memRes(i)(k) == r) dup = true; k += 1 }
      if (!dup) {
        memRes(i)(memCount(i)) = r; memCount(i) += 1
        val x = memUse(u)(r)
        if (x >= 1) memConflicts += 1
        memUse(u)(r) = x + 1
      }
    }
    private def register(i: Int): Unit = if (kind(i) == 3 && inMemory(i)) {
      val u = unit(i)
      memUnit(i) = u
      join(u, i, 1)
      if (isOutput(i)) addRead(i, u, outputsBy)
      val us = users(i)
      var k = 0
      while (k < us.length) { addRead(i, u, issue(us(k))); k += 1 }
    }
    private def refresh(i: Int): Unit = if (memory(i)) { unregister(i); register(i) }
    (0 until n).foreach(refresh)

    def run(steps: Long): Refined = {
      val movable = (0 until n).filter(i => kind(i) >= 2).toArray
      if (movable.isEmpty || steps <= 0) return start
      val hot = widths.flatten.maxOption.getOrElse(1).toDouble
      val cold = RefinementProblem.coldest
      val cooling = math.log(cold / hot)
      var temperature = hot
      def accept(delta: Double): Boolean = delta <= 0 || rng.nextDouble() < math.exp(-delta / temperature)
      var step = 0L
      while (step < steps) {
        if ((step & 1023) == 0) temperature = hot * math.exp(cooling * step.toDouble / steps)
        step += 1
        val i = movable(rng.nextInt(movable.length))
        val move = if (kind(i) == 3) rng.nextInt(3) else 2
        if (move == 0) {
          val us = classUnits(i)
          val to = us(rng.nextInt(us.length))
          val from = unit(i)
          if (to != from) {
            // the operation there, if any, trades places with this one
            val other = occupant(to)(residue(issue(i)))
            def bits =
              muxBits(from) + muxBits(to) + accumulatorBits(i) + (if (other >= 0) accumulatorBits(other)
                                                                  else 0L)
            val before = bits
            val p0 = memPenalty
            rebind(i, to)
            if (!accept(muxWeight * (bits - before) + memPenalty - p0)) rebind(i, from)
          }
        } else if (move == 1) {
          if (swappable(i)) {
            val before = muxBits(unit(i))
            swapPorts(i)
            if (!accept(muxWeight * (muxBits(unit(i)) - before))) swapPorts(i)
          }
        } else {
          val os = operands(i)
          var lo = Int.MinValue
          var k = 0
          while (k < os.length) { lo = math.max(lo, availableTo(os(k), i)); k += 1 }
          // readers keep their cycles: each still finds this value available
          var hi = lo + RefinementProblem.window * interval
          val us = users(i)
          k = 0
          while (k < us.length) {
            hi = math.min(hi, issue(us(k)) - (availableTo(i, us(k)) - issue(i))); k += 1
          }
          if (isOutput(i)) hi = math.min(hi, outputsBy - latency(i))
          // a chained multiply: ready by its root, within an interval of the rest of its chain
          if (chained(i)) {
            hi = math.min(hi, chainedBy(i) - latency(i))
            val members = chain(i)
            k = 0
            while (k < members.length) {
              if (members(k) != i) {
                lo = math.max(lo, ready(members(k)) - latency(i) - interval + 1)
                hi = math.min(hi, ready(members(k)) - latency(i) + interval - 1)
              }
              k += 1
            }
          }
          if (hi > lo) {
            val t = lo + rng.nextInt(hi - lo + 1)
            // and in a residue of its own among its chain's
            if (
              t != issue(i) && !(chained(i) && chain(i)
                .exists(m => m != i && residue(ready(m)) == residue(t + latency(i))))
            ) {
              val to =
                if (kind(i) != 3) -1
                else if (occupant(unit(i))(residue(t)) < 0 || residue(t) == residue(issue(i))) unit(i)
                else {
                  val us = classUnits(i)
                  var free = 0
                  k = 0
                  while (k < us.length) { if (occupant(us(k))(residue(t)) < 0) free += 1; k += 1 }
                  if (free == 0) -2
                  else {
                    var pick = rng.nextInt(free)
                    var chosen = -2
                    k = 0
                    while (k < us.length && chosen < 0) {
                      if (occupant(us(k))(residue(t)) < 0) { if (pick == 0) chosen = us(k) else pick -= 1 }
                      k += 1
                    }
                    chosen
                  }
                }
              if (to != -2) {
                val (t0, u0) = (issue(i), unit(i))
                val before = local(i, to)
                val p0 = memPenalty
                retime(i, t, to)
                val after = local(i, u0)
                if (!accept(after - before + memPenalty - p0)) retime(i, t0, u0)
              }
            }
          }
        }
      }
      val result = Refined(issue.toIndexedSeq, unit.toIndexedSeq, swapped.toIndexedSeq)
      check(result)
      if (cost(result) <= cost(start)) result else start
    }
  }
}

/**
 * Logic elements per bit of a registers-storage datapath's two scheduled costs, as the LE prediction fits
 * them to the open-tool estimate ([[reducerload.compiler.ResourceModel]] reads them from here).
 */
object LogicCost {

  /** A register bit holding a value between its cycles. */
  val heldBit: Double = 0.766

  /** An operand-multiplexer input bit beyond a port's first. */
  val muxBit: Double = 0.917

  /**
   * A held value's block-RAM delay: no logic element (its pointer is shared, its output register is the
   * block's), but an M9K of the device's few; weighed as this many logic elements. Measured on the UR5 at
   * 1e-3 N·m (sums reassociated, by height): at 0 the refined schedules take so many M9K that the fit needs
   * 21 clocks per sample instead of 17; at 10, 17 clocks with 57 M9K and 15,229 estimated LEs; at 40, 48 M9K
   * and ~250 LEs more.
   */
  val blockRamTap: Double = 10.0

  /**
   * Memory storage's product roundings ([[ProductAlignment]]): a bit of a rounding ahead of a product bank's
   * write register, and an input bit of an operand's shift multiplexer. Fitted to the open-tool estimate's
   * change when the xArm7, the Z1 and the Jaco went from a rounding per drop to fully aligned products
   * (docs/timing-closure.md). Weights for choosing among a unit's plans, not for predicting a design's LEs:
   * the prediction counts the shift multiplexers' inputs among its select inputs, with that feature's
   * coefficient fitted over the committed points.
   */
  val roundingBit: Double = 0.98
  val shiftMuxBit: Double = 0.79
}

object RefinementProblem {

  /** Intervals a node may move past the earliest cycle its operands allow, per move. */
  val window: Int = 3

  /** Final temperature of the annealing, in logic elements. */
  val coldest: Double = 0.3

  /** Registers a value may pass through per sample, at most (a key of the multiplexers' sources). */
  private val stageSpan: Long = 1L << 20
}
