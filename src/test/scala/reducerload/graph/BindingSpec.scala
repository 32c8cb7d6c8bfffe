package reducerload.graph

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.testutil.{ArmGolden, Seeds}
import reducerload.compiler.Compiler

import scala.util.Random

/**
 * The binding problem: every operation stays on a unit of its class, no two of one residue share a unit, and
 * the operand multiplexers get no more inputs than the list scheduler's binding gives them; on a case whose
 * best binding is known by hand it is found.
 */
class BindingSpec extends AnyFlatSpec {
  behavior of "BindingProblem"

  /** Multiplexer inputs beyond the first of every unit port, counted here from the binding alone. */
  private def inputs(problem: BindingProblem, units: IndexedSeq[Int]): Long =
    problem.ops.indices
      .groupBy(units)
      .map { case (u, on) =>
        problem
          .portBits(u)
          .indices
          .map(k => (on.map(problem.ops(_).sources(k)).distinct.size - 1).toLong * problem.portBits(u)(k))
          .sum
      }
      .sum

  private def checkValid(problem: BindingProblem, units: IndexedSeq[Int]): Unit = {
    assert(units.size == problem.ops.size)
    problem.ops.zip(units).foreach { case (o, u) => assert(o.units.contains(u), s"$o on unit $u") }
    val clashes = problem.ops.zip(units).groupBy { case (o, u) => (u, o.residue) }.filter(_._2.size > 1)
    assert(clashes.isEmpty, s"two operations on one unit in one residue: ${clashes.keys.mkString(", ")}")
  }

  private def held(n: Int) = PortSource.Held(NodeId(n), 0)

  it should "put the operations sharing an operand on one unit when the residues allow it" in {
    // residue 0: x*a and y*b; residue 1: x*c and y*d. The scheduler put x*a and y*d on unit 0: four sources
    // on each wide port. Best: x's products on one unit, y's on the other (one wide source each).
    val ops = IndexedSeq(
      BindOp(0 until 2, 0, IndexedSeq(held(1), held(10))),
      BindOp(0 until 2, 0, IndexedSeq(held(2), held(11))),
      BindOp(0 until 2, 1, IndexedSeq(held(1), held(12))),
      BindOp(0 until 2, 1, IndexedSeq(held(2), held(13)))
    )
    val problem = BindingProblem(ops, _ => IndexedSeq(30, 20))
    val start = IndexedSeq(0, 1, 1, 0)
    assert(inputs(problem, start) == 2 * 30 + 2 * 20)
    val best = problem.best(start)
    checkValid(problem, best)
    assert(best(0) == best(2) && best(1) == best(3), s"binding $best")
    assert(inputs(problem, best) == 2 * 20)
    assert(problem.cost(best) == inputs(problem, best))
  }

  it should "keep random bindings valid and never add multiplexer inputs" in {
    val rng = new Random(Seeds("binding-random", 91L))
    (1 to 40).foreach { trial =>
      val ii = 2 + rng.nextInt(20)
      val classes = 1 + rng.nextInt(3)
      val sizes = IndexedSeq.fill(classes)(1 + rng.nextInt(5))
      val ranges = sizes.indices.map(c => sizes.take(c).sum until sizes.take(c + 1).sum)
      val pool = 1 + rng.nextInt(30)
      def source() =
        if (rng.nextInt(4) == 0) PortSource.Literal(NodeId(rng.nextInt(pool)))
        else PortSource.Held(NodeId(rng.nextInt(pool)), rng.nextInt(3))
      // each class's units filled residue by residue to a random level, the start binding the first free unit
      val placed = ranges.flatMap { r =>
        (0 until ii).flatMap(res =>
          r.take(rng.nextInt(r.size + 1)).map(u => (BindOp(r, res, IndexedSeq(source(), source())), u))
        )
      }
      val problem = BindingProblem(placed.map(_._1), u => IndexedSeq(8 + u % 3, 5))
      val start = placed.map(_._2)
      val best = problem.best(start)
      checkValid(problem, best)
      assert(inputs(problem, best) <= inputs(problem, start), s"trial $trial")
      assert(problem.best(start) == best, s"trial $trial: not deterministic")
    }
  }

  it should "give the UR5's 17-clock units fewer operand inputs than one per operation" in {
    val config = ArmGolden.of("ur5").head.config
    val p = Compiler.arm(
      config.copy(
        targetError = Seq(1e-3),
        // the list scheduler's cycles, bound by BindingProblem (no refinement moving them)
        schedule = ScheduleRequest(clocksPerSample = Some(17), maxMultipliers = Some(66), refinement = 0)
      )
    )
    val s = p.schedule
    val g = p.graph
    val ii = s.clocksPerSample
    // counted here from the graph, the formats and the cycles: an operand is a constant's code, or a value's
    // register at the stage its reader's cycle needs; the wider operand on one port, the other on the other
    def sources(id: NodeId): Seq[(Int, Int, Int)] = {
      val Op.Mul(a, b) = g(id): @unchecked
      val issue = s.slot(id).get.issue
      val wideFirst = if (p.analysis(a).format.width >= p.analysis(b).format.width) Seq(a, b) else Seq(b, a)
      wideFirst.zipWithIndex.map { case (x, port) =>
        (port, x.index, s(x).fold(-1)(ready => (issue - ready) / ii))
      }
    }
    val muls = g.ids.filter(id => g(id).isInstanceOf[Op.Mul])
    val byUnit = muls.groupBy(id => s.slot(id).get.unit.get)
    val perOperation = byUnit.values.map(ops => 2L * (ops.size - 1)).sum
    val distinct = byUnit.values.map(ops => ops.flatMap(sources).distinct.size.toLong - 2).sum
    info(
      s"UR5 at 17 clocks: $distinct operand-multiplexer inputs beyond the first, $perOperation with one per operation"
    )
    // the ops reading one value are spread over every unit by the list scheduler; bound together they share
    assert(distinct * 10 < perOperation * 8, s"$distinct of $perOperation")
  }
}
