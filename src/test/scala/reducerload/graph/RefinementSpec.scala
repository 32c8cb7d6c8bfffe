package reducerload.graph

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.compiler.Compiler
import reducerload.testutil.{ArmGolden, Seeds}

import scala.util.Random

/**
 * The refinement of a registers-storage schedule: every rule of the schedule kept (dependences, forwarding,
 * one operation per unit and residue, the outputs' cycle), counted here from the solution alone; never more
 * multiplexer inputs and held registers than its start; deterministic; on cases whose best is known by hand
 * it is found; on the UR5 it takes a quarter of the multiplexer inputs off at the same latency.
 */
class RefinementSpec extends AnyFlatSpec {
  behavior of "RefinementProblem"
  import RefineNode._

  private def users(p: RefinementProblem): IndexedSeq[Seq[Int]] =
    p.nodes.indices.map(x => p.nodes.indices.filter(i => p.nodes(i).operands.contains(x)))

  private def ready(p: RefinementProblem, r: Refined, i: Int): Int = p.nodes(i) match {
    case Fixed(t, _)        => t
    case Own(_, l, _, _, _) => r.issue(i) + l
    case s: Shared          => r.issue(i) + s.latency
    case Literal(_)         => Int.MinValue
  }

  private def canForward(node: RefineNode): Boolean = node match {
    case s: Shared => s.forwardable
    case o: Own    => o.forwardable
    case _         => false
  }
  private def forwardable(p: RefinementProblem, x: Int): Boolean = canForward(p.nodes(x))
  private def takes(node: RefineNode): Boolean = node match {
    case o: Own => o.takesForwarded
    case _      => false
  }

  /** Every rule, checked here: an operand is read when ready, a product a cycle early by its one adder. */
  private def checkValid(p: RefinementProblem, r: Refined): Unit = {
    val us = users(p)
    p.nodes.indices.foreach { i =>
      p.nodes(i) match {
        case _: Own | _: Shared =>
          p.nodes(i).operands.foreach { x =>
            val early = forwardable(p, x) && us(x) == Seq(i) && takes(p.nodes(i))
            if (!p.nodes(x).isInstanceOf[Literal])
              assert(r.issue(i) >= ready(p, r, x) - (if (early) 1 else 0), s"node $i reads $x too early")
          }
        case _ =>
      }
      p.nodes(i) match {
        case s: Shared => assert(s.units.contains(r.unit(i)), s"node $i on unit ${r.unit(i)}")
        case _         =>
      }
    }
    val shared = p.nodes.indices.filter(p.nodes(_).isInstanceOf[Shared])
    val clashes =
      shared.groupBy(i => (r.unit(i), Math.floorMod(r.issue(i), p.interval))).filter(_._2.size > 1)
    assert(clashes.isEmpty, s"two operations on one unit in one residue: ${clashes.keys.mkString(", ")}")
    p.outputs.foreach(o => assert(ready(p, r, o) <= p.outputsBy, s"output $o ready after ${p.outputsBy}"))
  }

  /**
   * Multiplexer input bits beyond the first, held register bits and block-RAM delays, counted here: a value
   * read k intervals after it is ready takes k + 1 registers, or a block-RAM delay where k intervals reach
   * the problem's `memoryMinCycles`.
   */
  private def bits(p: RefinementProblem, r: Refined): (Long, Long, Int) = {
    val us = users(p)
    def source(x: Int, t: Int): (Int, Int) =
      if (p.nodes(x).isInstanceOf[Literal]) (x, -1) else (x, (t - ready(p, r, x)) / p.interval)
    val ports = p.nodes.indices.flatMap { i =>
      p.nodes(i) match {
        case s: Shared =>
          val order = if (r.swapped(i)) s.operands.reverse else s.operands
          order.zipWithIndex.map { case (x, k) => ((r.unit(i), k), source(x, r.issue(i))) }
        case _ => Nil
      }
    }
    val mux = ports
      .groupMap(_._1)(_._2)
      .map { case ((u, k), srcs) =>
        (srcs.distinct.size - 1).toLong * p.portWidths(u)(k)
      }
      .sum
    val held = p.nodes.indices.map { i =>
      val forwarded = forwardable(p, i) && us(i).size == 1 && takes(p.nodes(us(i).head)) &&
        r.issue(us(i).head) == ready(p, r, i) - 1
      val reads = us(i).map(r.issue) ++ (if (p.outputs.contains(i)) Seq(p.outputsBy) else Nil)
      if (p.nodes(i).isInstanceOf[Literal] || reads.isEmpty || forwarded) (0L, 0)
      else {
        val stages = reads.map(t => (t - ready(p, r, i)) / p.interval).distinct
        val inMemory =
          stages.filter(k => k >= 1 && p.memoryMinCycles > 0 && k * p.interval >= p.memoryMinCycles)
        val registers = (stages.diff(inMemory) :+ 0).max + 1
        (registers.toLong * p.nodes(i).width, inMemory.size)
      }
    }
    (mux, held.map(_._1).sum, held.map(_._2).sum)
  }

  /** A 12-bit product of latency 2 on `units`, neither swappable nor forwardable. */
  private def product(
      x: Int,
      y: Int,
      units: Range,
      chained: Option[Chained] = None,
      memory: Boolean = false
  ) =
    Shared(IndexedSeq(x, y), 2, 12, units, swappable = false, forwardable = false, chained, memory)

  private def weighted(p: RefinementProblem, b: (Long, Long, Int)) =
    p.muxWeight * b._1 + p.heldWeight * b._2 + p.tapWeight * b._3

  it should "put the products of one operand on one unit port" in {
    // II 2, x and y ready in cycle 4: x*a and y*b in cycle 4, x*c and y*d in cycle 5, started with x's products
    // on both units. Best: x's on one unit, y's on the other, one source on each wide port.
    val nodes = IndexedSeq(
      Fixed(4, 10), // 0 x
      Fixed(4, 10), // 1 y
      Literal(8), // 2 a
      Literal(8), // 3 b
      Literal(8), // 4 c
      Literal(8), // 5 d
      product(0, 2, 0 until 2), // 6 x*a
      product(1, 3, 0 until 2), // 7 y*b
      product(0, 4, 0 until 2), // 8 x*c
      product(1, 5, 0 until 2) // 9 y*d
    )
    val p = RefinementProblem(2, nodes, Seq(6, 7, 8, 9), 7, _ => IndexedSeq(10, 8), 1.0, 1.0)
    val start = Refined(
      IndexedSeq(-1, -1, -1, -1, -1, -1, 4, 4, 5, 5),
      IndexedSeq(-1, -1, -1, -1, -1, -1, 0, 1, 1, 0),
      IndexedSeq.fill(nodes.size)(false)
    )
    checkValid(p, start)
    assert(bits(p, start)._1 == 2 * 10 + 2 * 8)
    val best = p.anneal(start, 20000, 1L)
    checkValid(p, best)
    assert(best.unit(6) == best.unit(8) && best.unit(7) == best.unit(9), s"units ${best.unit}")
    assert(bits(p, best)._1 == 2 * 8)
    assert(p.cost(best) == weighted(p, bits(p, best)))
  }

  it should "keep an accumulated tree's products in residues of their own within an interval, ready by " +
    "their root, and gather them on one unit when its accumulator's input costs more than the operands'" in {
      // II 4, latency 2: x*a and y*b accumulate into a root ready in cycle 10, so by 8 (40-bit accumulator
      // input per unit beyond the first), z*c on its own; started on two units. Gathered on one, they add
      // 10 + 8 operand multiplexer bits and save 40.
      val chain = Some(Chained(9, 40))
      val nodes = IndexedSeq(
        Fixed(0, 10), // 0 x
        Fixed(0, 10), // 1 y
        Fixed(0, 10), // 2 z
        Literal(8), // 3 a
        Literal(8), // 4 b
        Literal(8), // 5 c
        product(0, 3, 0 until 2, chain), // 6 x*a
        product(1, 4, 0 until 2, chain), // 7 y*b
        product(2, 5, 0 until 2), // 8 z*c
        Fixed(10, 14) // 9 the root
      )
      val p = RefinementProblem(4, nodes, Seq(8, 9), 10, _ => IndexedSeq(10, 8), 1.0, 1.0)
      val start = Refined(
        IndexedSeq(-1, -1, -1, -1, -1, -1, 2, 3, 2, -1),
        IndexedSeq(-1, -1, -1, -1, -1, -1, 0, 1, 1, -1),
        IndexedSeq.fill(nodes.size)(false)
      )
      checkValid(p, start)
      val best = p.anneal(start, 20000, 1L)
      checkValid(p, best)
      val ready = Seq(6, 7).map(best.issue(_) + 2)
      assert(ready.map(_ % 4).distinct.size == 2 && (ready.max - ready.min) < 4, s"issues ${best.issue}")
      assert(ready.max <= 8, s"issues ${best.issue}")
      assert(best.unit(6) == best.unit(7), s"units ${best.unit}")
    }

  it should "issue a sum late enough that its reader takes it from its first register" in {
    // II 2. v = x + y issued in cycle 0 is read by v*e in cycle 5, three registers in; x*y reads x and y in
    // cycle 6. Issued in cycle 3 or later (or its reader earlier), v is read from its first register.
    val nodes = IndexedSeq(
      Fixed(0, 10), // 0 x
      Fixed(0, 10), // 1 y
      Own(IndexedSeq(0, 1), 1, 11), // 2 v
      Literal(8), // 3 e
      Shared(IndexedSeq(2, 3), 2, 12, 0 until 2, swappable = false, forwardable = false), // 4 v*e
      Shared(IndexedSeq(0, 1), 2, 12, 0 until 2, swappable = true, forwardable = false) // 5 x*y
    )
    val p = RefinementProblem(2, nodes, Seq(4, 5), 8, _ => IndexedSeq(12, 12), 1.0, 1.0)
    val start =
      Refined(IndexedSeq(-1, -1, 0, -1, 5, 6), IndexedSeq(-1, -1, -1, -1, 0, 0), IndexedSeq.fill(6)(false))
    checkValid(p, start)
    val best = p.anneal(start, 20000, 1L)
    checkValid(p, best)
    assert((best.issue(4) - ready(p, best, 2)) / 2 == 0, s"issues ${best.issue}")
    assert(weighted(p, bits(p, best)) < weighted(p, bits(p, start)))
  }

  it should "move the reads of products into their unit's memory window, apart on its read port" in {
    // II 6, one unit, latency 2: p = x*a issued in 0 (ready 2), q = y*b issued in 1 (ready 3), read by v = p + z
    // and w = q + z in the cycles they are ready, so each product takes a register; both are outputs by 12. In
    // memory, p is read in 5..8 and q in 6..9 (ProductMemory.readDelay = 3 after ready, within the interval),
    // in two residues of the one read port: then neither takes a register.
    assert(ProductMemory.readDelay == 3)
    val nodes = IndexedSeq(
      Fixed(0, 10), // 0 x
      Fixed(0, 10), // 1 y
      Fixed(0, 10), // 2 z
      Literal(8), // 3 a
      Literal(8), // 4 b
      product(0, 3, 0 until 1, memory = true), // 5 p
      product(1, 4, 0 until 1, memory = true), // 6 q
      Own(IndexedSeq(5, 2), 1, 13), // 7 v
      Own(IndexedSeq(6, 2), 1, 13) // 8 w
    )
    val p = RefinementProblem(6, nodes, Seq(7, 8), 12, _ => IndexedSeq(10, 8), 1.0, 1.0)
    val start = Refined(
      IndexedSeq(-1, -1, -1, -1, -1, 0, 1, 2, 3),
      IndexedSeq(-1, -1, -1, -1, -1, 0, 0, -1, -1),
      IndexedSeq.fill(nodes.size)(false)
    )
    checkValid(p, start)
    assert(p.memoryConflicts(start) == 0)
    val best = p.anneal(start, 20000, 1L)
    checkValid(p, best)
    val reads = Seq(7, 8).map(best.issue)
    reads.zip(Seq(5, 6)).foreach { case (t, x) =>
      assert(t >= ready(p, best, x) + 3 && t <= ready(p, best, x) + 6, s"issues ${best.issue}")
    }
    assert(reads.map(_ % 6).distinct.size == 2, s"issues ${best.issue}")
    assert(p.memoryConflicts(best) == 0)
    // in memory, p and q take none of the registers counted here (12 bits each per interval to their read)
    val saved = Seq(5 -> 7, 6 -> 8).map { case (x, v) =>
      ((best.issue(v) - ready(p, best, x)) / 6 + 1) * 12.0
    }
    assert(p.cost(best) == weighted(p, bits(p, best)) - saved.sum)
    // both read by one addition in one cycle: one of them stays out of the memory, a conflict
    val sum = p.copy(nodes = nodes.take(7) :+ Own(IndexedSeq(5, 6), 1, 13), outputs = Seq(7))
    val late = Refined(
      IndexedSeq(-1, -1, -1, -1, -1, 0, 1, 7),
      IndexedSeq(-1, -1, -1, -1, -1, 0, 0, -1),
      IndexedSeq.fill(8)(false)
    )
    checkValid(sum, late)
    assert(sum.memoryConflicts(late) == 1)
    // on two units each product is alone: no memory for one member, so each keeps its register
    val two = p.copy(nodes = nodes.map {
      case s: Shared => s.copy(units = 0 until 2)
      case n         => n
    })
    val apart = Refined(
      IndexedSeq(-1, -1, -1, -1, -1, 0, 1, 5, 6),
      IndexedSeq(-1, -1, -1, -1, -1, 0, 1, -1, -1),
      IndexedSeq.fill(nodes.size)(false)
    )
    checkValid(two, apart)
    assert(two.loneMemberBits(apart) == 2 * 12)
    assert(two.cost(apart) == weighted(two, bits(two, apart)))
  }

  /** A random problem and a valid start: each node at the first cycle its operands allow and a unit frees. */
  private def randomProblem(rng: Random): (RefinementProblem, Refined) = {
    val ii = 2 + rng.nextInt(10)
    val classes = 1 + rng.nextInt(2)
    val sizes = IndexedSeq.fill(classes)(1 + rng.nextInt(3))
    val ranges = sizes.indices.map(c => sizes.take(c).sum until sizes.take(c + 1).sum)
    val fixed = 2 + rng.nextInt(4)
    val ops = 6 + rng.nextInt(40)
    // kinds first (no more multiplies than the units have slots), then operands from earlier values, then
    // forwarding from the uses
    val slots = sizes.min * ii
    val kinds = IndexedSeq.fill(fixed)(0) ++ IndexedSeq.fill(2)(1) ++
      IndexedSeq
        .fill(ops)(2 + rng.nextInt(2))
        .scanLeft((0, 0)) { case ((_, muls), k) =>
          if (k == 3 && muls < slots) (3, muls + 1) else (2, muls)
        }
        .tail
        .map(_._1)
    val operands = kinds.indices.map { i =>
      val values = (0 until i).filter(kinds(_) != 1)
      kinds(i) match {
        case 2 => IndexedSeq(values(rng.nextInt(values.size)), values(rng.nextInt(values.size)))
        case 3 =>
          val literals = (0 until i).filter(kinds(_) == 1)
          IndexedSeq(
            values(rng.nextInt(values.size)),
            if (rng.nextBoolean()) literals(rng.nextInt(literals.size)) else values(rng.nextInt(values.size))
          )
        case _ => IndexedSeq.empty
      }
    }
    val readers = kinds.indices.map(x => kinds.indices.filter(i => operands(i).contains(x)))
    val outputs = kinds.indices.filter(i => kinds(i) >= 2 && readers(i).isEmpty)
    val nodes: IndexedSeq[RefineNode] = kinds.indices.map { i =>
      val w = 4 + rng.nextInt(20)
      val uses = kinds.indices.map(j => operands(j).count(_ == i)).sum + (if (outputs.contains(i)) 1 else 0)
      kinds(i) match {
        case 0 => Fixed(1 + rng.nextInt(3), w)
        case 1 => Literal(w)
        // some additions with one reader stand for shift-and-add products, whose reader may take them early
        case 2 =>
          Own(operands(i), 1 + rng.nextInt(3), w, uses == 1 && !outputs.contains(i) && rng.nextBoolean())
        case _ =>
          Shared(
            operands(i),
            2 + rng.nextInt(4),
            w,
            ranges(rng.nextInt(ranges.size)),
            swappable = rng.nextBoolean(),
            forwardable = uses == 1 && !outputs.contains(i)
          )
      }
    }
    val issue = Array.fill(nodes.size)(-1)
    val unit = Array.fill(nodes.size)(-1)
    val taken = scala.collection.mutable.Set.empty[(Int, Int)]
    def readyAt(i: Int): Int = nodes(i) match {
      case Fixed(t, _)        => t
      case Own(_, l, _, _, _) => issue(i) + l
      case s: Shared          => issue(i) + s.latency
      case Literal(_)         => Int.MinValue
    }
    nodes.indices.foreach { i =>
      nodes(i) match {
        case Own(os, _, _, _, _) =>
          issue(i) =
            os.map(x => if (canForward(nodes(x)) && takes(nodes(i))) readyAt(x) - 1 else readyAt(x)).max
        case s: Shared =>
          val earliest = s.operands.map(readyAt).max
          val (t, u) = Iterator
            .from(earliest)
            .flatMap(t => s.units.find(u => !taken((u, t % ii))).map(u => (t, u)))
            .next()
          issue(i) = t
          unit(i) = u
          taken += ((u, t % ii))
        case _ =>
      }
    }
    val outputsBy = outputs.map(readyAt).max + rng.nextInt(4)
    val problem =
      RefinementProblem(ii, nodes, outputs, outputsBy, u => IndexedSeq(6 + u % 5, 4 + u % 3), 0.9, 0.8)
    (problem, Refined(issue.toIndexedSeq, unit.toIndexedSeq, IndexedSeq.fill(nodes.size)(false)))
  }

  it should "keep random problems valid, never cost more than the start and give the same answer every run" in {
    val seed = Seeds("refinement-random", 33L)
    val rng = new Random(seed)
    (1 to 60).foreach { trial =>
      val (p, start) = randomProblem(rng)
      checkValid(p, start)
      val refined = p.anneal(start, 200L * p.nodes.size, trial.toLong)
      withClue(s"seed $seed trial $trial: ") {
        checkValid(p, refined)
        assert(weighted(p, bits(p, refined)) <= weighted(p, bits(p, start)) + 1e-9)
        assert(p.anneal(start, 200L * p.nodes.size, trial.toLong) == refined, "not deterministic")
      }
    }
  }

  it should "take a quarter of the UR5's operand-multiplexer inputs off at 17 clocks, at no more latency" in {
    val config = ArmGolden.of("ur5").head.config
    def at(refinement: Int) = Compiler
      .arm(
        config.copy(
          targetError = Seq(1e-3),
          schedule =
            ScheduleRequest(clocksPerSample = Some(17), maxMultipliers = Some(66), refinement = refinement)
        )
      )
      .schedule
    val list = at(0)
    val refined = at(ScheduleRequest.defaultRefinement)
    // counted here from the graph and the cycles: a port reads a constant's code or a value's register at the
    // stage its reader's cycle needs
    def inputs(s: Schedule): Long = {
      val g = s.analysis.graph
      val muls = g.ids.filter(id => s.slot(id).exists(_.unit.isDefined) && g(id).isInstanceOf[Op.Mul])
      muls
        .flatMap { id =>
          val t = s.slot(id).get.issue
          s.ports(id).zipWithIndex.map { case (x, k) =>
            ((s.slot(id).get.unit.get, k), (x.index, s(x).fold(-1)(r => (t - r) / s.clocksPerSample)))
          }
        }
        .groupMap(_._1)(_._2)
        .map { case ((u, k), srcs) => (srcs.distinct.size - 1).toLong * s.unitShape(u).widths(k) }
        .sum
    }
    info(
      s"UR5 at 17 clocks: ${inputs(list)} operand-multiplexer input bits and ${list.heldBits} held bits with " +
        s"the list schedule (bound), ${inputs(refined)} and ${refined.heldBits} refined; latency ${list.latency} " +
        s"and ${refined.latency}"
    )
    assert(refined.latency <= list.latency)
    assert(inputs(refined) * 4 <= inputs(list) * 3, s"${inputs(refined)} of ${inputs(list)}")
    assert(refined.heldBits < list.heldBits)
  }
}
