package reducerload.graph

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.compiler.Compiler
import reducerload.testutil.ArmGolden

/**
 * The solver's shortest registers-storage schedule (`schedule.scheduler = cp-sat`): on a case whose optimum
 * is known by hand it is found and proved; where the hint is already the shortest there is nothing to take;
 * on the UR5 at 17 clocks with registered routes it is shorter than the list schedule and no shorter than the
 * dependences allow, every rule counted here from the graph and the schedule's cycles, the same every run.
 */
class LatencySearchSpec extends AnyFlatSpec {
  behavior of "LatencySearch"
  import RefineNode._

  // II 2, one unit. x and y ready in cycle 0; p = x*x and q = y*y take 3 clocks, s = p + q one. The hint puts
  // q a whole interval late (residue 1 in cycle 3, not 1): s ready in 7. By hand: p in 0, q in 1 (the other
  // residue), s issued in 4, ready in 5.
  private val nodes = IndexedSeq(
    Fixed(0, 10), // 0 x
    Fixed(0, 10), // 1 y
    Shared(IndexedSeq(0, 0), 3, 12, 0 until 1, swappable = false, forwardable = false), // 2 p
    Shared(IndexedSeq(1, 1), 3, 12, 0 until 1, swappable = false, forwardable = false), // 3 q
    Own(IndexedSeq(2, 3), 1, 13) // 4 s
  )
  private def problem(by: Int) = RefinementProblem(2, nodes, Seq(4), by, _ => IndexedSeq(10, 10), 1.0, 1.0)
  private def solution(p: Int, q: Int, s: Int) =
    Refined(IndexedSeq(-1, -1, p, q, s), IndexedSeq(-1, -1, 0, 0, -1), IndexedSeq.fill(5)(false))

  it should "find the shortest schedule of a case known by hand, and prove it" in {
    val found = LatencySearch(problem(7), solution(0, 3, 6)).getOrElse(fail("no shorter schedule"))
    assert(found.outputsBy == 5 && found.optimal && found.provedBound == 5, s"$found")
    val r = found.solution
    assert(r.issue(2) % 2 != r.issue(3) % 2, s"p and q in one residue of the one unit: ${r.issue}")
    assert(
      r.issue(4) >= math.max(r.issue(2), r.issue(3)) + 3,
      s"s reads a product before it is ready: ${r.issue}"
    )
  }

  it should "leave a schedule that is already the shortest" in {
    assert(LatencySearch(problem(5), solution(0, 1, 4)).isEmpty)
  }

  it should "move an accumulated chain's products, and its root with them, within the chain's rules" in {
    // II 4, two units, latency 2: p = x*a and q = y*b accumulate into r (ready two clocks after the later
    // of them: the term register, then the adder), s = r + z. The hint issues them in 5 and 6: r in 10, s
    // ready in 11. By hand: p in 0, q in 1 (its product ready in a residue of its own, though the other unit
    // is free in 0), r in 5, s ready in 6.
    val chain = Some(Chained(6, 14))
    def product(x: Int, y: Int) =
      Shared(IndexedSeq(x, y), 2, 12, 0 until 2, swappable = false, forwardable = false, chained = chain)
    val chained = IndexedSeq(
      Fixed(0, 10), // 0 x
      Fixed(0, 10), // 1 y
      Literal(8), // 2 a
      Literal(8), // 3 b
      product(0, 2), // 4 p
      product(1, 3), // 5 q
      Fixed(10, 14), // 6 r, its cycle the hint's
      Fixed(0, 14), // 7 z
      Own(IndexedSeq(6, 7), 1, 15) // 8 s
    )
    val p = RefinementProblem(4, chained, Seq(8), 11, _ => IndexedSeq(10, 8), 1.0, 1.0)
    val hint = Refined(
      IndexedSeq(-1, -1, -1, -1, 5, 6, -1, -1, 10),
      IndexedSeq(-1, -1, -1, -1, 0, 0, -1, -1, -1),
      IndexedSeq.fill(chained.size)(false)
    )
    p.check(hint)
    val found = LatencySearch(p, hint).getOrElse(fail("no shorter schedule"))
    assert(found.outputsBy == 6 && found.optimal, s"$found")
    assert(found.problem.nodes(6) == Fixed(5, 14), s"the root: ${found.problem.nodes(6)}")
    val r = found.solution
    assert(Set(r.issue(4), r.issue(5)) == Set(0, 1) && r.issue(8) == 5, s"issues ${r.issue}")
  }

  it should "shorten the UR5's list schedule at 17 clocks with registered routes, within every rule" in {
    val config = ArmGolden.of("ur5").head.config
    def at(scheduler: Scheduler) = Compiler
      .arm(
        config.copy(
          targetError = Seq(1e-3),
          schedule = ScheduleRequest(
            clocksPerSample = Some(17),
            maxMultipliers = Some(66),
            listOrder = Some(ListOrder.ByHeight),
            refinement = 0,
            scheduler = scheduler
          ),
          datapath = config.datapath.copy(reassociate = Reassociation.Sums, registeredRoutes = Some(true))
        )
      )
      .schedule
    val list = at(Scheduler.ListOnly)
    val solved = at(Scheduler.CpSat)
    info(
      s"UR5 at 17 clocks: dependence bound ${solved.dependenceBound}, list schedule ${list.latency}, " +
        s"CP-SAT ${solved.latency} (${solved.shorter
            .fold("none shorter")(s => if (s.optimal) "optimal" else "not proved")})"
    )
    assert(solved.latency < list.latency, s"CP-SAT ${solved.latency}, the list ${list.latency}")
    assert(solved.latency >= solved.dependenceBound)
    // every rule from the graph: an operation after its operands are in their registers (registered routes
    // forward no product), a unit one multiply per residue
    val g = solved.analysis.graph
    g.ids.foreach { id =>
      solved.slot(id).filter(_ => !g(id).isInstanceOf[Op.Input] && !g(id).isInstanceOf[Op.Trig]).foreach {
        sl =>
          g(id).operands
            .foreach(x => solved(x).foreach(r => assert(sl.issue >= r, s"node ${id.index} reads ${x.index}")))
      }
    }
    val onUnits = g.ids.flatMap(id =>
      solved.slot(id).filter(_ => g(id).isInstanceOf[Op.Mul]).flatMap(_.unit.map(id -> _))
    )
    val clashes =
      onUnits.groupBy { case (id, u) => (u, solved.slot(id).get.issue % 17) }.filter(_._2.size > 1)
    assert(clashes.isEmpty, s"two multiplies on one unit in one residue: ${clashes.keys.mkString(", ")}")
    val again = at(Scheduler.CpSat)
    assert(g.ids.map(again.slot) == g.ids.map(solved.slot), "two runs, two schedules")
  }
}
