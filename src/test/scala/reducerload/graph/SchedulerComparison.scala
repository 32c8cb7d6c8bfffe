package reducerload.graph

import com.google.ortools.Loader
import com.google.ortools.sat._
import reducerload.app.Cli

/**
 * The refinement ([[RefinementProblem.anneal]]) against a maintained solver on the same problem: OR-Tools
 * CP-SAT, given the same moves (each multiply's cycle, unit and port order, each addition's cycle) and the
 * same rules, minimising operand-multiplexer inputs and held register bits. A benchmark, not a test:
 *
 * {{{
 * ./sbt "Test/runMain reducerload.graph.SchedulerComparison 60 --robot golden/robots/ur5_robot.urdf --tip tool0
 *   --max-acceleration 15 --target-error 1e-3 --schedule.list-order by-height --datapath.reassociate sums
 *   --clocks-per-sample 17"
 * }}}
 *
 * The first argument is CP-SAT's time limit in seconds; the rest is a design as `run emit` takes it. The
 * table gives each solution's bits as [[RefinementProblem.bits]] counts them (every register of a value a
 * source of its own) and its latency. CP-SAT's model counts a value read on one port as one input whatever
 * its register (a register per interval would need a variable per value, unit, port and stage); it reads its
 * solution's true count from the same function.
 */
object SchedulerComparison {

  def main(args: Array[String]): Unit = {
    val seconds = args.head.toDouble
    val cli = Cli.parse("emit", args.tail.toSeq, Nil)
    val arm = cli.compiled.arm
    val request = arm.scheduleRequest
    def scheduleWith(refinement: Int) =
      new Schedule(
        arm.analysis,
        request.copy(refinement = refinement),
        arm.cordic,
        arm.multiplierLatency,
        reducerload.arm.ArmDatapath.inputCycle,
        arm.memoryDelayMinCycles,
        arm.datapath.registeredRoutes
      )
    val list = scheduleWith(0)
    val (problem, start) = list.refinementProblem.getOrElse(
      throw new IllegalArgumentException(
        "the comparison needs registers storage at 2 clocks per sample or more"
      )
    )
    val bound = Refined(
      start.issue,
      problem.nodes.indices.map(i =>
        list.slot(NodeId(i)).flatMap(_.unit).filter(_ => start.unit(i) >= 0).getOrElse(-1)
      ),
      start.swapped
    )
    def timed[T](f: => T): (T, Double) = {
      val t0 = System.nanoTime()
      val r = f
      (r, (System.nanoTime() - t0) / 1e9)
    }
    val steps = ScheduleRequest.defaultRefinement.toLong * problem.nodes.count {
      case _: RefineNode.Own | _: RefineNode.Shared => true
      case _                                        => false
    }
    val (annealed, annealSeconds) = timed(problem.anneal(start, steps, Schedule.refinementSeed))
    val (fromList, listSeconds) = timed(cpSat(problem, start, seconds))
    val (fromAnnealed, annealedSeconds) = timed(cpSat(problem, annealed, seconds))
    def latency(r: Refined): Int =
      problem.outputs.map { o =>
        problem.nodes(o) match {
          case RefineNode.Own(_, l, _, _, _) => r.issue(o) + l
          case s: RefineNode.Shared          => r.issue(o) + s.latency
          case RefineNode.Fixed(t, _)        => t
          case RefineNode.Literal(_)         => 0
        }
      }.max + list.outputStages
    def row(name: String, r: Refined, secs: String): String = {
      problem.check(r)
      val (mux, held, delays) = problem.bits(r)
      f"| $name | $mux | $held | $delays | ${problem.cost(r)}%.0f | ${latency(r)} | $secs |"
    }
    println(
      s"${arm.moduleName}: ${list.clocksPerSample} clocks per sample, ${list.multiplierUnits} multiplier units"
    )
    println(
      s"| schedule | operand-multiplexer input bits | held register bits | block-RAM delays | cost (LEs, a delay as ${LogicCost.blockRamTap}) | latency | seconds |"
    )
    println("| --- | --- | --- | --- | --- | --- | --- |")
    println(row("list scheduler", start, "-"))
    println(row("list scheduler, bound (BindingProblem)", bound, "-"))
    println(
      row(
        s"refinement, ${ScheduleRequest.defaultRefinement} steps per operation",
        annealed,
        f"$annealSeconds%.1f"
      )
    )
    fromList.foreach(r => println(row(s"CP-SAT from the list schedule, $seconds s", r, f"$listSeconds%.1f")))
    fromAnnealed.foreach(r =>
      println(row(s"CP-SAT from the refinement, $seconds s", r, f"$annealedSeconds%.1f"))
    )
  }

  /** The refinement's problem for CP-SAT, hinted with `hint`; its best solution within `seconds`. */
  def cpSat(problem: RefinementProblem, hint: Refined, seconds: Double): Option[Refined] = {
    import RefineNode._
    Loader.loadNativeLibraries()
    val m = new CpModel()
    val nodes = problem.nodes
    val ii = problem.interval
    val horizon = problem.outputsBy + ii
    val timing = new CpTiming(m, problem, horizon)
    import timing.{ready, residue, shared, start}
    val users = nodes.indices.map(x => nodes.indices.filter(i => nodes(i).operands.contains(x)))
    problem.outputs
      .filterNot(nodes(_).isInstanceOf[Literal])
      .foreach(o => m.addLessOrEqual(ready(o), problem.outputsBy))
    val on = shared.map { i =>
      val s = nodes(i).asInstanceOf[Shared]
      i -> s.units.map(u => u -> m.newBoolVar(s"x${i}_$u")).toMap
    }.toMap
    val intervals =
      scala.collection.mutable.Map.empty[Int, Vector[IntervalVar]].withDefaultValue(Vector.empty)
    shared.foreach { i =>
      m.addExactlyOne(on(i).values.toArray[com.google.ortools.sat.Literal])
      on(i).foreach { case (u, b) =>
        intervals(u) = intervals(u) :+ m.newOptionalFixedSizeIntervalVar(residue(i), 1, b, s"slot${i}_$u")
      }
    }
    intervals.values.foreach(ivs => m.addNoOverlap(ivs.toArray))
    val swapped = shared.map { i =>
      val o = m.newBoolVar(s"o$i")
      if (!nodes(i).asInstanceOf[Shared].swappable) m.addEquality(o, 0)
      i -> o
    }.toMap
    val source = scala.collection.mutable.Map.empty[(Int, Int, Int), BoolVar]
    def reads(x: Int, u: Int, k: Int) = source.getOrElseUpdate((x, u, k), m.newBoolVar(s"y${x}_${u}_$k"))
    shared.foreach { i =>
      val Seq(a, b) = nodes(i).operands
      on(i).foreach { case (u, x) =>
        val o = swapped(i)
        m.addBoolOr(Array[com.google.ortools.sat.Literal](x.not(), o, reads(a, u, 0)))
        m.addBoolOr(Array[com.google.ortools.sat.Literal](x.not(), o, reads(b, u, 1)))
        m.addBoolOr(Array[com.google.ortools.sat.Literal](x.not(), o.not(), reads(b, u, 0)))
        m.addBoolOr(Array[com.google.ortools.sat.Literal](x.not(), o.not(), reads(a, u, 1)))
      }
    }
    // held bits: a register per interval from ready to the last read (forwarding not modelled: counted after)
    val objective = LinearExpr.newBuilder()
    val scale = 1000.0
    source.foreach { case ((_, u, k), y) =>
      objective.addTerm(y, math.round(problem.muxWeight * scale * problem.portWidths(u)(k)))
    }
    nodes.indices.foreach { x =>
      if (!nodes(x).isInstanceOf[Literal] && (users(x).nonEmpty || problem.outputs.contains(x))) {
        val last = m.newIntVar(0, horizon, s"last$x")
        users(x).foreach(u => m.addGreaterOrEqual(last, start(u).get))
        if (problem.outputs.contains(x)) m.addGreaterOrEqual(last, problem.outputsBy)
        val span = m.newIntVar(-horizon, horizon, s"span$x")
        m.addEquality(
          span,
          LinearExpr
            .newBuilder()
            .add(last)
            .addTerm(start(x).getOrElse(m.newConstant(0)), -1)
            .add(
              nodes(x) match {
                case Fixed(t, _)        => -t
                case Own(_, l, _, _, _) => -l
                case s: Shared          => -s.latency
                case _                  => 0
              }
            )
            .build()
        )
        val stages = m.newIntVar(-horizon, horizon, s"stages$x")
        m.addDivisionEquality(stages, span, m.newConstant(ii))
        objective.addTerm(stages, math.round(problem.heldWeight * scale * nodes(x).width))
      }
    }
    m.minimize(objective.build())
    shared.foreach { i =>
      m.addHint(start(i).get, hint.issue(i))
      on(i).foreach { case (u, b) => m.addHint(b, if (hint.unit(i) == u) 1L else 0L) }
      m.addHint(swapped(i), if (hint.swapped(i)) 1L else 0L)
    }
    nodes.indices.foreach(i => if (nodes(i).isInstanceOf[Own]) m.addHint(start(i).get, hint.issue(i)))
    val solver = new CpSolver()
    solver.getParameters.setMaxTimeInSeconds(seconds).setNumWorkers(2).setRandomSeed(1)
    val status = solver.solve(m)
    if (status != CpSolverStatus.OPTIMAL && status != CpSolverStatus.FEASIBLE) None
    else
      Some(
        Refined(
          nodes.indices.map(i => start(i).fold(-1)(v => solver.value(v).toInt)),
          nodes.indices.map(i =>
            on.get(i).fold(-1)(_.collectFirst { case (u, b) if solver.booleanValue(b) => u }.get)
          ),
          nodes.indices.map(i => swapped.get(i).exists(solver.booleanValue))
        )
      )
  }
}

/**
 * The list scheduler's latency against the shortest the solver finds for the same registers-storage problem
 * ([[LatencySearch]], `schedule.scheduler = cp-sat`), and the design's after the refinement. A benchmark, not
 * a test:
 *
 * {{{
 * ./sbt "Test/runMain reducerload.graph.LatencyComparison --robot golden/robots/ur5_robot.urdf --tip tool0
 *   --max-acceleration 15 --target-error 1e-3 --max-multipliers 66 --clocks-per-sample 17
 *   --schedule.list-order by-height --datapath.registered-routes true"
 * }}}
 *
 * The arguments are a design as `run emit` takes it. One table row, latencies with the output stage: the
 * dependence bound of the report (every unit free when asked, every angle read from its first cycle), the
 * list schedule's, the solver's and the least it proved (the sin/cos at the list's cycles), the seconds it
 * took.
 */
object LatencyComparison {

  def main(args: Array[String]): Unit = {
    val cli = Cli.parse("emit", args.toSeq, Nil)
    val arm = cli.compiled.arm
    val list = new Schedule(
      arm.analysis,
      arm.scheduleRequest.copy(refinement = 0, scheduler = Scheduler.ListOnly),
      arm.cordic,
      arm.multiplierLatency,
      reducerload.arm.ArmDatapath.inputCycle,
      arm.memoryDelayMinCycles,
      arm.datapath.registeredRoutes
    )
    val (problem, hint) = list.refinementProblem.getOrElse(
      throw new IllegalArgumentException(
        "the comparison needs registers storage at 2 clocks per sample or more"
      )
    )
    val t0 = System.nanoTime()
    val found = LatencySearch(problem, hint)
    val secs = (System.nanoTime() - t0) / 1e9
    val stages = list.outputStages
    val (best, proved) = found.fold(("none shorter", "-")) { s =>
      (s"${s.outputsBy + stages}${if (s.optimal) " (optimal)" else ""}", s"${s.provedBound + stages}")
    }
    println(
      "| design | clocks per sample | multiplier units | dependence bound | list scheduler | CP-SAT | CP-SAT's bound | seconds |"
    )
    println("| --- | --- | --- | --- | --- | --- | --- | --- |")
    println(
      f"| ${arm.moduleName} | ${list.clocksPerSample} | ${list.multiplierUnits} | ${list.dependenceBound} | ${list.latency} | $best | $proved | $secs%.1f |"
    )
  }
}
