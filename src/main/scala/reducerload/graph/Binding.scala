package reducerload.graph

/**
 * What a shared unit's operand port selects from: a value's register (a node's, at one stage of its chain of
 * registers written once per sample), a constant's code, or the word of a block RAM a CORDIC unit writes.
 */
sealed trait PortSource
object PortSource {
  final case class Held(node: NodeId, stage: Int) extends PortSource
  final case class Literal(node: NodeId) extends PortSource

  /** The word register of [[Schedule.sinCosMemories]]' `memory`: every value it serves, one input. */
  final case class SinCosWord(memory: Int) extends PortSource
}

/**
 * One operation to bind to a unit: the units it may run on (its class's, all of one shape), its residue
 * modulo the interval, and the source on each of its ports.
 */
final case class BindOp(units: Range, residue: Int, sources: IndexedSeq[PortSource])

/**
 * The binding problem of a modulo schedule (the scheduling problem's cycles fixed): give each operation a
 * unit of its class, no two operations of one residue on the same unit, so that the units' operand
 * multiplexers have the fewest inputs. A port's multiplexer has one input per distinct source of the
 * operations on its unit, so operations sharing an operand (the products of one sin/cos, of one velocity)
 * belong together. The units of a class are interchangeable in the schedule (its cycles depend only on how
 * many units each residue uses), so the binding changes no cycle.
 *
 * @param portBits
 *   the width of each port of each unit (an input of that multiplexer costs that many bits)
 */
final case class BindingProblem(ops: IndexedSeq[BindOp], portBits: Int => IndexedSeq[Int]) {

  /** Multiplexer input bits beyond the first of every unit port, under a unit per operation. */
  def cost(units: IndexedSeq[Int]): Long =
    ops.indices
      .groupBy(units)
      .toSeq
      .map { case (u, on) =>
        portBits(u).indices.map { k =>
          (on.map(ops(_).sources(k)).distinct.size - 1).toLong * portBits(u)(k)
        }.sum
      }
      .sum

  /**
   * A binding at most as costly as `start` (a valid one, the list scheduler's): the cheapest of `start`
   * [[improved]], [[greedy]] improved and `start` itself (annealing may end above its start), the first on a
   * tie. Deterministic.
   */
  def best(start: IndexedSeq[Int]): IndexedSeq[Int] =
    Seq(improved(start), improved(greedy), start).minBy(cost)

  /**
   * Operations in order, each to the unit of its class free in its residue that already has the most of its
   * sources (by bits), the first on a tie.
   */
  def greedy: IndexedSeq[Int] = {
    val taken = scala.collection.mutable.Set.empty[(Int, Int)]
    val seen = scala.collection.mutable.Set.empty[(Int, Int, PortSource)]
    ops.map { o =>
      val free = o.units.filterNot(u => taken((u, o.residue)))
      require(free.nonEmpty, s"BindingProblem: no unit free in residue ${o.residue}")
      val u =
        free.maxBy(u => o.sources.indices.filter(k => seen((u, k, o.sources(k)))).map(portBits(u)(_)).sum)
      taken += ((u, o.residue))
      o.sources.indices.foreach(k => seen += ((u, k, o.sources(k))))
      u
    }
  }

  /**
   * `start` improved: seeded annealing, then a descent. A move trades an operation's unit with the operation
   * on another unit of its class in its residue (or moves it there if that unit is free there); the descent
   * keeps a move only if it removes multiplexer input bits, pass after pass until none does (at most
   * [[BindingProblem.maxPasses]]).
   */
  def improved(start: IndexedSeq[Int]): IndexedSeq[Int] = {
    require(start.size == ops.size, s"BindingProblem: ${start.size} units for ${ops.size} operations")
    val unit = start.toArray
    // operations on each (unit, port, source), and distinct sources on each (unit, port)
    val count = scala.collection.mutable.Map.empty[(Int, Int, PortSource), Int].withDefaultValue(0)
    val distinct = scala.collection.mutable.Map.empty[(Int, Int), Int].withDefaultValue(0)
    def add(o: Int, sign: Int): Unit = ops(o).sources.zipWithIndex.foreach { case (src, k) =>
      val key = (unit(o), k, src)
      if (sign > 0 && count(key) == 0) distinct((unit(o), k)) += 1
      count(key) += sign
      if (sign < 0 && count(key) == 0) distinct((unit(o), k)) -= 1
    }
    // the operation on each (unit, residue)
    val at = scala.collection.mutable.Map.empty[(Int, Int), Int]
    def place(o: Int, u: Int): Unit = { unit(o) = u; at((u, ops(o).residue)) = o; add(o, 1) }
    def lift(o: Int): Unit = { add(o, -1); at.remove((unit(o), ops(o).residue)) }
    ops.indices.foreach(o => place(o, unit(o)))
    def unitCost(u: Int): Long = portBits(u).indices.map(k => distinct((u, k)).toLong * portBits(u)(k)).sum
    // o (on its unit) and the operation on `to` in its residue, if any, trade units
    def swap(o: Int, to: Int): Unit = {
      val from = unit(o)
      val other = at.get((to, ops(o).residue))
      lift(o)
      other.foreach(lift)
      place(o, to)
      other.foreach(place(_, from))
    }
    @scala.annotation.tailrec
    def passes(left: Int): Unit = {
      val better = ops.indices.map { o =>
        ops(o).units.filter(_ != unit(o)).count { to =>
          val from = unit(o)
          val before = unitCost(from) + unitCost(to)
          swap(o, to)
          val kept = unitCost(from) + unitCost(to) < before
          if (!kept) {
            // back: the operation now on `from` in this residue (if any) returns to `to`
            swap(o, from)
          }
          kept
        }
      }.sum
      if (better > 0 && left > 1) passes(left - 1)
    }
    // Annealing first (seeded: the same binding every run): a random operation trades units with its residue's
    // occupant of another unit of its class, kept if it saves bits or, less and less often, if it costs some,
    // so the search leaves the local minima a pure descent stops in; then the descent.
    val rng = new scala.util.Random(BindingProblem.seed)
    val movable = ops.indices.filter(o => ops(o).units.size > 1).toIndexedSeq
    val steps = BindingProblem.annealingSteps * movable.size
    val hot = if (ops.isEmpty) 1.0 else ops.indices.map(o => portBits(unit(o)).sum).max.toDouble
    (0 until (if (movable.isEmpty) 0 else steps)).foreach { i =>
      val o = movable(rng.nextInt(movable.size))
      val to = ops(o).units(rng.nextInt(ops(o).units.size))
      val from = unit(o)
      if (to != from) {
        val before = unitCost(from) + unitCost(to)
        swap(o, to)
        val delta = unitCost(from) + unitCost(to) - before
        val temperature = hot * math.pow(BindingProblem.coldest / hot, i.toDouble / steps)
        if (delta > 0 && rng.nextDouble() >= math.exp(-delta / temperature)) swap(o, from)
      }
    }
    passes(BindingProblem.maxPasses)
    unit.toIndexedSeq
  }
}

object BindingProblem {

  /** Improvement passes at most (each pass tries every operation on every other unit of its class). */
  val maxPasses: Int = 50

  /** Annealing steps per operation, its fixed seed and its final temperature (bits). */
  val annealingSteps: Int = 100
  val seed: Long = 1L
  val coldest: Double = 0.5
}
