package reducerload.graph

import com.google.ortools.Loader
import com.google.ortools.sat._

/**
 * The timing part of a CP-SAT model of a [[RefinementProblem]]: an issue cycle in 0..`horizon` for each
 * operation that moves, and its dependences (an operand read when ready, a forwardable one a cycle early by a
 * reader that takes it off its operator); each shared multiply's residue modulo the interval; each
 * accumulated root [[Accumulation.rootDelay]] after the last product of its chain, the chain's products ready
 * in residues of their own within an interval. [[LatencySearch]] and the refinement's comparison
 * (graph/SchedulerComparison, a test) build on it.
 */
final class CpTiming(m: CpModel, problem: RefinementProblem, horizon: Int) {
  import RefineNode._
  private val nodes = problem.nodes
  private val ii = problem.interval
  val start: IndexedSeq[Option[IntVar]] = nodes.indices.map { i =>
    nodes(i) match {
      case _: Own | _: Shared => Some(m.newIntVar(0, horizon, s"t$i"))
      case _                  => None
    }
  }

  private def issuedReady(i: Int, latency: Int): LinearExpr =
    LinearExpr.newBuilder().add(start(i).get).add(latency).build()

  /** Each accumulated root's chain: the cycle its last product is ready (the root's is rootDelay later). */
  val lastOfChain: Map[Int, IntVar] = problem.chains.map { case (root, members) =>
    val readies = members.map(i => issuedReady(i, nodes(i).asInstanceOf[Shared].latency))
    val latest = horizon + members.map(nodes(_).asInstanceOf[Shared].latency).max
    val last = m.newIntVar(0, latest, s"last$root")
    val first = m.newIntVar(0, latest, s"first$root")
    m.addMaxEquality(last, readies.toArray[LinearArgument])
    m.addMinEquality(first, readies.toArray[LinearArgument])
    m.addLessOrEqual(LinearExpr.newBuilder().add(last).addTerm(first, -1).build(), ii - 1)
    m.addAllDifferent(
      members
        .zip(readies)
        .map { case (i, r) =>
          val v = m.newIntVar(0, ii - 1, s"q$i")
          m.addModuloEquality(v, r, ii)
          v: LinearArgument
        }
        .toArray
    )
    root -> last
  }

  /** The cycle node `x`'s value is in its register. */
  def ready(x: Int): LinearExpr = nodes(x) match {
    case _: Fixed if lastOfChain.contains(x) =>
      LinearExpr.newBuilder().add(lastOfChain(x)).add(Accumulation.rootDelay).build()
    case Fixed(t, _)        => LinearExpr.constant(t)
    case Own(_, l, _, _, _) => issuedReady(x, l)
    case s: Shared          => issuedReady(x, s.latency)
    case Literal(_)         => LinearExpr.constant(0)
  }

  nodes.indices.foreach { i =>
    nodes(i) match {
      case _: Own | _: Shared =>
        nodes(i).operands.filterNot(nodes(_).isInstanceOf[Literal]).distinct.foreach { x =>
          val early =
            (nodes(i) match { case o: Own => o.takesForwarded; case _ => false }) && (nodes(x) match {
              case s: Shared => s.forwardable
              case o: Own    => o.forwardable
              case _         => false
            })
          m.addGreaterOrEqual(
            start(i).get,
            LinearExpr.newBuilder().add(ready(x)).add(if (early) -1 else 0).build()
          )
        }
      case _ =>
    }
  }

  /** The multiplies on shared units. */
  val shared: IndexedSeq[Int] = nodes.indices.filter(nodes(_).isInstanceOf[Shared])

  /** Each shared multiply's issue cycle modulo the interval: the residue whose unit slot it takes. */
  val residue: Map[Int, IntVar] = shared.map { i =>
    val r = m.newIntVar(0, problem.interval - 1, s"r$i")
    m.addModuloEquality(r, start(i).get, problem.interval)
    i -> r
  }.toMap
}

/**
 * A shorter schedule found by [[LatencySearch]]: a solution of `problem` (the searched one with every output
 * ready by `outputsBy` and each accumulated root where the solver moved its chain), `provedBound` the least
 * any schedule of the problem can give (equal when `optimal`), each multiply on a unit of its class.
 */
final case class ShorterSchedule(
    problem: RefinementProblem,
    provedBound: Int,
    optimal: Boolean,
    solution: Refined
) {
  def outputsBy: Int = problem.outputsBy
}

/**
 * The registers-storage modulo schedule with the shortest latency, on a maintained solver (OR-Tools CP-SAT):
 * each operation's issue cycle under the dependences of its [[RefinementProblem]] and at most `n` multiplies
 * of a class of `n` units per residue, the inputs and the sin/cos at the cycles the problem fixes; minimised,
 * the cycle the last output is ready. The list scheduler's schedule is the hint and the fallback: by height,
 * it leaves the UR5 at 17 clocks per sample 6 cycles above the dependence bound, where the solver proves the
 * optimum one above it in about a second. The refinement then works at the shorter latency with less slack,
 * hence more operand-multiplexer inputs (the UR5: about 5 % more logic elements), so the list schedule stays
 * the default (docs/timing-closure.md).
 *
 * Deterministic: one worker, a fixed seed and a limit in the solver's deterministic time, not the clock's.
 */
object LatencySearch {

  /** The solver's limit, in its deterministic seconds (about a second of one core each). */
  val limit: Double = 20.0

  /** A schedule of `problem` shorter than `hint` (which must keep its rules), if the solver finds one. */
  def apply(problem: RefinementProblem, hint: Refined, limit: Double = limit): Option[ShorterSchedule] = {
    import RefineNode._
    Loader.loadNativeLibraries()
    val m = new CpModel()
    val nodes = problem.nodes
    val ii = problem.interval
    val timing = new CpTiming(m, problem, problem.outputsBy)
    import timing.{lastOfChain, ready, residue, shared, start}
    val makespan = m.newIntVar(0, problem.outputsBy, "makespan")
    problem.outputs
      .filterNot(nodes(_).isInstanceOf[Literal])
      .foreach(o => m.addLessOrEqual(ready(o), makespan))
    shared.groupBy(nodes(_).asInstanceOf[Shared].units).foreach { case (units, ops) =>
      val c = m.addCumulative(units.size.toLong)
      ops.foreach(i => c.addDemand(m.newFixedSizeIntervalVar(residue(i), 1, s"slot$i"), 1L))
    }
    m.minimize(makespan)
    nodes.indices.foreach(i => start(i).foreach(v => m.addHint(v, hint.issue(i))))
    val solver = new CpSolver()
    solver.getParameters.setMaxDeterministicTime(limit).setNumWorkers(1).setRandomSeed(1)
    val status = solver.solve(m)
    val found = status == CpSolverStatus.OPTIMAL || status == CpSolverStatus.FEASIBLE
    Option
      .when(found && solver.value(makespan) < problem.outputsBy) {
        val issue = nodes.indices.map(i => start(i).fold(-1)(v => solver.value(v).toInt))
        // each residue's multiplies of a class on its units in turn (the refinement or the binding moves them)
        val unit = Array.fill(nodes.size)(-1)
        shared.groupBy(i => (nodes(i).asInstanceOf[Shared].units, Math.floorMod(issue(i), ii))).foreach {
          case ((units, _), ops) => ops.zip(units).foreach { case (i, u) => unit(i) = u }
        }
        ShorterSchedule(
          problem.withRoots(
            lastOfChain.map { case (root, last) =>
              root -> (solver.value(last).toInt + Accumulation.rootDelay)
            },
            solver.value(makespan).toInt
          ),
          math.ceil(solver.bestObjectiveBound - 1e-9).toInt,
          status == CpSolverStatus.OPTIMAL,
          Refined(issue, unit.toIndexedSeq, nodes.map(_ => false))
        )
      }
      .map { s => s.problem.check(s.solution); s }
  }
}
