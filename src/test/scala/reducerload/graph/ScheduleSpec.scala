package reducerload.graph

import reducerload.testutil.CompiledParams
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.arm.ArmParams
import reducerload.compiler.{Compiler, TargetFit}
import reducerload.pipeline.PipelinedMultiplier
import reducerload.testutil.ArmGolden

/**
 * The modulo schedule's promises, checked from the graph and the hardware's timing rules, not from the
 * schedule's own bookkeeping: every operand is ready when read, no unit takes two operations in one residue,
 * every value is read before a later sample overwrites it, the budget holds; and infeasible requests are
 * refused naming the setting.
 */
class ScheduleSpec extends AnyFlatSpec {
  behavior of "Schedule"

  private lazy val ur5: ArmParams = Compiler.arm(ArmGolden.of("ur5").head.config)
  private lazy val planar3: ArmParams = Compiler.arm(ArmGolden.of("planar3").head.config)

  private def scheduled(p: ArmParams, request: ScheduleRequest): ArmParams = p.copy(scheduleRequest = request)

  /** The UR5 with registered routes, scheduled as `request` asks. */
  private def routed(request: ScheduleRequest): ArmParams =
    scheduled(ur5.copy(datapath = ur5.datapath.copy(registeredRoutes = Some(true))), request)

  /** Checks a schedule against the rules it must obey; returns it for figures. */
  private def check(p: ArmParams): Schedule = {
    val s = p.schedule
    val g = p.graph
    val ii = s.clocksPerSample
    // Registered routes (shared registers storage): two registered multiplexer levels before a unit, so 2
    // clocks more per multiply; the OR of the saturations gets a register of its own.
    val routed = p.datapath.registeredRoutes.getOrElse(ii > Schedule.directMaxClocks) && ii > 1 &&
      s.request.stored == Storage.Registers
    // The CORDIC start table's block RAM gets a register in logic wherever routes are registered (any storage).
    val tableRegister =
      if (
        p.cordic.tableBits > 0 && !p.cordic.tableRouteRegister &&
        p.datapath.registeredRoutes.getOrElse(ii > Schedule.directMaxClocks)
      ) 1
      else 0
    // Clocks from an operation's issue to its value in a register, from the hardware's timing rules.
    def latency(id: NodeId): Int = g(id) match {
      case Op.Mul(_, _) =>
        val shape = s.unitShape(s.slot(id).get.unit.get)
        val rounds = p.analysis.productRounding(id).drop > 0 &&
          p.productRounding != reducerload.fixedpoint.Rounding.Truncate
        PipelinedMultiplier.latency(shape.wide, shape.narrow) + p.multiplierLatency - 1 +
          (if (ii > 1 || rounds) 1 else 0) + (if (routed) 2 else 0)
      case Op.Trig(_, _) =>
        1 + p.cordic.latency + tableRegister + (if (ii > 1 || s.cordicUnits < g.angles.size) 1 else 0)
      case Op.Const(_) => 0
      case _           => 1
    }
    g.ids.foreach { id =>
      val op = g(id)
      op match {
        case Op.Const(_) => assert(s(id).isEmpty)
        case _ =>
          val issue = s.slot(id).get.issue
          // an accumulated tree's sums read no operand: the accumulator takes its products (checked below)
          val accumulated = s.accumulation(id).exists(_.sums.contains(id))
          op.operands.filterNot(_ => accumulated).foreach { x =>
            // A forwarded product is read off its unit's output, the cycle before its register would hold it.
            val readable = s(x).map(r => if (s.forwarded(x)) r - 1 else r)
            readable.foreach(ready =>
              assert(
                ready <= issue,
                s"node ${id.index} reads node ${x.index} in cycle $issue, ready only in $ready"
              )
            )
            if (s.forwarded(x)) {
              assert(
                readable.get == issue,
                s"forwarded node ${x.index} read in cycle $issue, on the unit's " +
                  s"output only in ${readable.get}"
              )
              assert(
                g.ids.count(u => g(u).operands.contains(x)) == 1 && !g.outputs.exists(_.node == x),
                s"forwarded node ${x.index} has other readers"
              )
              assert(op.isInstanceOf[Op.Add] || op.isInstanceOf[Op.Sub] || op.isInstanceOf[Op.Neg])
            }
          }
          op match {
            case Op.Mul(a, b) =>
              val own = MulShape.of(p.analysis(a).format.width, p.analysis(b).format.width)
              val shape = s.unitShape(s.slot(id).get.unit.get)
              assert(
                shape.wide >= own.wide && shape.narrow >= own.narrow,
                s"node ${id.index}: a $own multiply on a $shape unit"
              )
            case _ =>
          }
          assert(
            s(id).get == issue + latency(id),
            s"node ${id.index} ($op): ready ${s(id).get}, issued $issue + latency ${latency(id)}"
          )
      }
    }
    // An accumulated tree: its products, each read by the tree alone, are in their units' registers of
    // rounded products (in the cycle their own register would hold them) in residues of their own within an
    // interval, so that one accumulator takes them all: each into its term register the clock after, and
    // the accumulator's adder writes the root's register from there, two clocks after the last product, the
    // tree's sums with it.
    s.accumulations.foreach { a =>
      val out = a.products.map(q => s(q).get)
      assert(out.map(_ % ii).distinct.size == out.size, s"tree ${a.root.index}: two products in one residue")
      assert(out.max - out.min < ii, s"tree ${a.root.index}: products over more than an interval")
      a.sums.foreach(x =>
        assert(s(x).get == out.max + 2, s"tree ${a.root.index}: sum ${x.index} not ready then")
      )
      a.products.foreach { q =>
        assert(
          !s.forwarded(q) && g.readers(q.index) == 1,
          s"tree ${a.root.index}: product ${q.index} read elsewhere"
        )
        assert(p.heldTaps(q).isEmpty, s"tree ${a.root.index}: product ${q.index} has a register")
      }
      a.inner.foreach(x =>
        assert(p.heldTaps(x).isEmpty, s"tree ${a.root.index}: sum ${x.index} has a register")
      )
    }
    // One operation per unit and residue; every multiply and every angle on a unit.
    val mulSlots = g.ids.filter(g(_).isInstanceOf[Op.Mul]).map(id => s.slot(id).get)
    assert(
      mulSlots.map(sl => (sl.unit.get, sl.issue % ii)).distinct.size == mulSlots.size,
      "two multiplies share a unit in one residue"
    )
    assert(mulSlots.forall(_.unit.get < s.multiplierUnits))
    val angleSlots = g.angles.map(s.angleSlot)
    assert(
      angleSlots.map(sl => (sl.unit.get, sl.issue % ii)).distinct.size == angleSlots.size,
      "two angles share a CORDIC unit in one residue"
    )
    // Readers: the output stage reads after every output is ready; latency is that plus its registers.
    g.outputs.foreach(o => assert(s(o.node).get <= s.outputsReady))
    assert(s.latency == g.outputs.map(o => s(o.node).get).max + (if (routed) 3 else 2))
    // Past registered routes only products within schedule.forward-slack of a longest path of the
    // dependences (units free, nothing forwarded; angles from cycle 1, inputs when the schedule has them).
    if (routed) {
      val asap = g.ids.foldLeft(Vector.empty[Int]) { (r, id) =>
        r :+ (g(id) match {
          case Op.Const(_) => 0
          case Op.Input(_) => s(id).get
          // a sum of several angles passes a register of its own first
          case Op.Trig(_, a) => Schedule.firstAngleCycle + (if (a.weight > 1) 1 else 0) + latency(id)
          case op            => op.operands.map(x => r(x.index)).max + latency(id)
        })
      }
      val tail = g.ids.reverse.foldLeft(Map.empty[Int, Int]) { (t, id) =>
        val readers = g.ids.filter(u => g(u).operands.contains(id))
        t + (id.index -> readers.map(u => latency(u) + t(u.index)).maxOption.getOrElse(0))
      }
      val longest = g.outputs.map(o => asap(o.node.index)).max
      g.ids.filter(s.forwarded).foreach { x =>
        val slack = longest - asap(x.index) - tail(x.index)
        assert(
          s.request.forwardSlack.exists(slack <= _),
          s"node ${x.index} forwarded past its registered route with slack $slack, " +
            s"schedule.forward-slack ${s.request.forwardSlack}"
        )
      }
    }
    // The dependences' latency (printed in the report's limits) is one no schedule beats.
    assert(
      s.dependenceBound <= s.latency,
      s"dependence bound ${s.dependenceBound} above latency ${s.latency}"
    )
    s.request.maxMultipliers.foreach(b =>
      assert(s.multiplierBlocks <= b, s"${s.multiplierBlocks} blocks above the budget $b")
    )
    assert(s.multiplierUnits.toLong * ii >= mulSlots.size)
    s
  }

  private def figures(label: String, p: ArmParams): Unit = {
    val s = p.schedule
    println(
      f"[schedule] $label%-28s II ${s.clocksPerSample}%3d  mul units " +
        f"${s.multiplierUnits}%3d (${s.unitSummary}%-20s) blocks ${s.multiplierBlocks}%4d  cordic " +
        f"${s.cordicUnits}%2d  latency ${s.latency}%4d  held bits ${s.heldBits}%7d"
    )
  }

  it should "give every operation its own operator at one sample per clock (the ASAP schedule)" in {
    Seq("planar3" -> planar3, "ur5" -> ur5).foreach { case (name, p) =>
      val s = check(p)
      figures(s"$name II=1", p)
      assert(s.clocksPerSample == 1 && s.dedicated && s.multiplierUnits == p.graph.counts.multiplications)
      // With an operator per operation the schedule is the dependences' bound itself.
      assert(s.dependenceBound == s.latency, s"$name: bound ${s.dependenceBound}, ASAP latency ${s.latency}")
      // ASAP: each node ready at the latest operand plus its own latency, nothing later.
      p.graph.ids.foreach { id =>
        val earliest = p.graph(id).operands.flatMap(s(_)).maxOption.getOrElse(0)
        p.graph(id) match {
          case _: Op.Mul | _: Op.Add | _: Op.Sub | _: Op.Neg =>
            assert(s.slot(id).get.issue == earliest, s"node ${id.index} not ASAP")
          case _ =>
        }
      }
    }
  }

  it should "share multipliers and CORDIC units at any interval, within budget" in {
    Seq(2, 3, 7, 16, 40).foreach { ii =>
      Seq("planar3" -> planar3, "ur5" -> ur5).foreach { case (name, p) =>
        val q = scheduled(p, ScheduleRequest(clocksPerSample = Some(ii)))
        check(q)
        figures(s"$name II=$ii", q)
      }
    }
    val shared = scheduled(planar3, ScheduleRequest(clocksPerSample = Some(3), cordicUnits = Some(1)))
    assert(check(shared).cordicUnits == 1)
  }

  it should "derive the fewest clocks per sample from a multiplier budget" in {
    Seq(66, 40, 16, ur5.schedule.classes.map(_.shape.blocks).sum + ur5.cordic.multiplierBlocks).foreach {
      budget =>
        val q = scheduled(ur5, ScheduleRequest(clocksPerSample = None, maxMultipliers = Some(budget)))
        val s = check(q)
        figures(s"ur5 budget $budget", q)
        assert(s.multiplierBlocks <= budget)
        // One clock fewer would need more blocks than the budget.
        if (s.clocksPerSample > 1) {
          val tighter = scala.util.Try(
            scheduled(ur5, ScheduleRequest(Some(s.clocksPerSample - 1), Some(budget))).schedule
          )
          assert(
            tighter.isFailure,
            s"budget $budget: ${s.clocksPerSample - 1} clocks per sample would also fit"
          )
        }
    }
  }

  it should "print a floor on clocks per sample that no schedule within the budget beats" in {
    // Every schedule the list scheduler finds within a budget is at or above the floor for that budget, and a
    // larger budget never raises the floor; the floor counts block-clocks, so halving the budget at least
    // does not lower it.
    Seq(66, 40, 19).foreach { budget =>
      val q = scheduled(ur5, ScheduleRequest(clocksPerSample = None, maxMultipliers = Some(budget)))
      val s = q.schedule
      val floor = s.clocksLowerBound(budget).get
      assert(
        floor <= s.clocksPerSample,
        s"budget $budget: floor $floor above the achieved ${s.clocksPerSample}"
      )
      assert(s.clocksLowerBound(budget * 2).get <= floor)
      assert(s.multiplierUtilization > 0.0 && s.multiplierUtilization <= 1.0)
      // The floor is at least the block-clocks the products need, counted here from the operand formats.
      val g = q.graph
      val blockClocks = g.ids.collect {
        case id if g(id).isInstanceOf[Op.Mul] && !s.shiftAdded(id) => s.shapeOf(id).blocks
      }.sum
      assert(
        floor.toLong * budget >= blockClocks,
        s"budget $budget: $floor clocks hold fewer than $blockClocks"
      )
      info(
        s"ur5 budget $budget: floor $floor, achieved ${s.clocksPerSample}, multiplier slots used " +
          f"${s.multiplierUtilization * 100}%.1f%%"
      )
    }
  }

  it should "refuse infeasible requests naming the setting and what would work" in {
    def refusal(r: ScheduleRequest): String =
      intercept[IllegalArgumentException](scheduled(ur5, r).schedule).getMessage
    val least = ur5.schedule.classes.map(_.shape.blocks).sum + ur5.cordic.multiplierBlocks
    val few = refusal(ScheduleRequest(None, Some(least - 1)))
    assert(few.contains("schedule.max-multipliers") && few.contains(s"use at least $least"), few)
    val tight = refusal(ScheduleRequest(Some(2), Some(66)))
    assert(tight.contains("schedule.max-multipliers = 66") && tight.contains("clocks-per-sample >="), tight)
    val cordic = refusal(ScheduleRequest(Some(1), None, Some(1)))
    assert(cordic.contains("schedule.cordic-units = 1"), cordic)
    assert(
      intercept[IllegalArgumentException](ScheduleRequest(Some(0))).getMessage
        .contains("schedule.clocks-per-sample")
    )
    val shiftAddInBanks = intercept[IllegalArgumentException](
      ScheduleRequest(
        Some(8),
        storage = Some(Storage.Memory),
        constantMultiplies = ConstantMultiplies.ShiftAdd
      )
    )
    assert(
      shiftAddInBanks.getMessage.contains(
        "schedule.constant-multiplies = shift-add needs schedule.storage = registers"
      ),
      shiftAddInBanks.getMessage
    )
  }

  it should "pass every route between units through registers (datapath.registered-routes): 2 clocks more " +
    "per multiply on a unit, no product forwarded, a three-register output stage" in {
      Seq(2, 17, 40).foreach { ii =>
        Seq("planar3" -> planar3, "ur5" -> ur5).foreach { case (name, p) =>
          val request = ScheduleRequest(clocksPerSample = Some(ii))
          val direct =
            check(scheduled(p.copy(datapath = p.datapath.copy(registeredRoutes = Some(false))), request))
          val routes = scheduled(p.copy(datapath = p.datapath.copy(registeredRoutes = Some(true))), request)
          val routed = check(routes)
          figures(s"$name II=$ii routed", routes)
          assert(routed.routed && !direct.routed)
          assert(
            routed.latency > direct.latency,
            s"$name II=$ii: routed ${routed.latency}, direct ${direct.latency}"
          )
        }
      }
      // One clock per sample has no shared unit and so no route to register.
      assert(!check(ur5.copy(datapath = ur5.datapath.copy(registeredRoutes = Some(true)))).routed)
    }

  it should "accumulate trees of products when schedule.accumulate-slack asks, each root the signed sum of " +
    "its products as the bit-accurate model computes them, and no tree without it" in {
      def at(slack: Option[Int], scheduler: Scheduler = Scheduler.ListOnly) = {
        val request =
          ScheduleRequest(clocksPerSample = Some(18), accumulateSlack = slack, scheduler = scheduler)
        val p = routed(if (scheduler == Scheduler.CpSat) request.copy(refinement = 0) else request)
        figures(s"ur5 II=18 routed accumulate-slack ${slack.fold("none")(_.toString)} $scheduler", p)
        (p, check(p))
      }
      val (_, none) = at(None)
      val (_, critical) = at(Some(0))
      val (p, loose) = at(Some(9))
      // The solver moves the chained products and their roots with them (check: within every rule, the
      // dependence bound of the accumulated trees no higher).
      val (_, solved) = at(Some(9), Scheduler.CpSat)
      println(
        s"[schedule] trees accumulated: none ${none.accumulations.size}, slack 0 ${critical.accumulations.size}, " +
          s"slack 9 ${loose.accumulations.size} (latency ${loose.latency}, with the solver ${solved.latency}, " +
          s"bound ${solved.dependenceBound})"
      )
      assert(none.accumulations.isEmpty && critical.accumulations.nonEmpty)
      assert(loose.accumulations.size >= critical.accumulations.size)
      assert(solved.accumulations.nonEmpty && solved.latency < loose.latency)
      // Each root against its products in the model's values of seeded random samples: the sum the
      // accumulator computes (each product aligned to the root's fraction bits, subtracted where negated).
      val model = new GraphModel(p.analysis)
      val rng = new scala.util.Random(reducerload.testutil.Seeds("accumulated-roots", 70L))
      def code(limit: BigInt) = BigInt(limit.bitLength + 1, rng.self) mod (2 * limit + 1) - limit
      (1 to 20).foreach { _ =>
        val values = model.nodeValues(
          SampleCodes(
            IndexedSeq.fill(p.chain.size)(BigInt(p.numerics.angleBits, rng.self)),
            p.numerics.velocityLimitRaw.map(code).toIndexedSeq,
            p.numerics.accelerationLimitRaw.map(code).toIndexedSeq
          )
        )
        loose.accumulations.foreach { a =>
          val root = p.analysis(a.root).format.fracBits
          val sum = a.terms.map { t =>
            val v = values(t.product.index) << (root - p.analysis(t.product).format.fracBits)
            if (t.negated) -v else v
          }.sum
          assert(
            sum == values(a.root.index),
            s"tree ${a.root.index}: products sum to $sum, the root is ${values(a.root.index)}"
          )
        }
      }
    }

  it should "forward past registered routes only the products schedule.forward-slack names, the longest " +
    "paths' first, for a shorter latency" in {
      def at(slack: Option[Int]) = {
        val p = routed(ScheduleRequest(clocksPerSample = Some(17), forwardSlack = slack))
        figures(s"ur5 II=17 routed forward-slack ${slack.fold("none")(_.toString)}", p)
        val s = check(p)
        (s, p.graph.ids.count(s.forwarded))
      }
      val (none, noneForwarded) = at(None)
      val (critical, criticalForwarded) = at(Some(0))
      val (all, allForwarded) = at(Some(4096))
      println(
        s"[schedule] forwarded products: none $noneForwarded, slack 0 $criticalForwarded, any $allForwarded"
      )
      assert(noneForwarded == 0 && criticalForwarded > 0 && allForwarded > criticalForwarded)
      assert(
        critical.dependenceBound < none.dependenceBound && all.dependenceBound <= critical.dependenceBound
      )
      assert(critical.latency < none.latency, s"slack 0: ${critical.latency} cycles, none: ${none.latency}")
    }

  it should "register the routes by itself above a few clocks per sample (datapath.registered-routes = auto)" in {
    val auto = planar3.copy(datapath = planar3.datapath.copy(registeredRoutes = None))
    def routedAt(ii: Int, storage: Storage) =
      scheduled(auto, ScheduleRequest(clocksPerSample = Some(ii), storage = Some(storage))).schedule.routed
    assert(!routedAt(1, Storage.Registers) && !routedAt(4, Storage.Registers))
    assert(routedAt(5, Storage.Registers) && routedAt(17, Storage.Registers))
    // memory storage's routes pass registers already
    assert(!routedAt(17, Storage.Memory))
  }

  it should "place the UR5's operations by height with registers within every rule (schedule.list-order = " +
    "by-height)" in {
      val request = ScheduleRequest(maxMultipliers = Some(66))
      val inOrder = check(scheduled(ur5, request))
      val byHeight = check(scheduled(ur5, request.copy(listOrder = Some(ListOrder.ByHeight))))
      info(
        s"UR5 in 66 blocks: latency ${inOrder.latency} in the graph's order, ${byHeight.latency} by height"
      )
      assert(byHeight.clocksPerSample == inOrder.clocksPerSample)
      assert(byHeight.multiplierBlocks == inOrder.multiplierBlocks)
    }
}

/**
 * `numeric.target-error`: the fewest fraction bits whose derived bounds meet the target, checked against one
 * bit fewer.
 */
class TargetErrorSpec extends AnyFlatSpec {
  behavior of "numeric.target-error"

  private lazy val ur5 = ArmGolden.of("ur5").head.config

  it should "pick the fewest fraction bits that meet the target on every joint" in {
    Seq(1e-2, 1e-3, 4e-4).foreach { target =>
      val p = Compiler.arm(ur5.copy(targetError = Seq(target)))
      assert(p.errorBounds.forall(_ <= target), s"target $target: bounds ${p.errorBounds}")
      val fewer =
        TargetFit.fitted(p, Seq.fill(p.chain.size)(Double.MaxValue)) // any bits meet this: the fewest allowed
      val oneLess = scala.util.Try(
        p.copy(datapath = p.datapath.shifted(-1))
      )
      oneLess.foreach(q =>
        assert(
          q.errorBounds.zipWithIndex.exists { case (b, _) => b > target },
          s"target $target: one bit fewer also meets it"
        )
      )
      // No kind of value can lose a bit on its own either (the fit narrows each kind after the common shift).
      val kinds = Seq[(String, ArmParams => ArmParams)](
        "velocity" -> (q => q.copy(datapath = q.datapath.copy(velocityFracBits = q.velocityFracBits - 1))),
        "acceleration" -> (q =>
          q.copy(datapath = q.datapath.copy(accelerationFracBits = q.accelerationFracBits - 1))
        ),
        "constant" -> (q => q.copy(datapath = q.datapath.copy(constantFracBits = q.constantFracBits - 1))),
        "internal" -> (q => q.copy(datapath = q.datapath.copy(internalFracBits = q.internalFracBits - 1))),
        "output" -> (q => q.copy(datapath = q.datapath.copy(outputFracBits = q.outputFracBits - 1)))
      )
      // (With per-node caps chosen, the constants' and products' minimality is each node's, checked below.)
      kinds
        .filter { case (kind, _) => p.fracBitLimits.isEmpty || !Set("constant", "internal")(kind) }
        .foreach { case (kind, less) =>
          scala.util
            .Try(less(p))
            .flatMap(q => scala.util.Try(q.errorBounds))
            .foreach(bounds =>
              assert(bounds.exists(_ > target), s"target $target: one $kind fraction bit fewer also meets it")
            )
        }
      TargetErrorSpec.checkNodes(p, Seq.fill(p.chain.size)(target), s"ur5 target $target")
      assert(fewer.internalFracBits <= p.internalFracBits)
      println(
        f"[target] ur5 target $target%.0e N·m: internal frac bits ${p.internalFracBits}, " +
          f"worst bound ${p.errorBound}%.3e, " +
          s"widest node ${p.analysis.widest._2.format}, " +
          s"${p.copy(scheduleRequest = ScheduleRequest(None, Some(66))).schedule.unitSummary}"
      )
    }
    val perJoint = Compiler.arm(ur5.copy(targetError = Seq(1e-3, 1e-3, 1e-3, 1e-4, 1e-4, 1e-5)))
    assert(perJoint.errorBounds.zip(Seq(1e-3, 1e-3, 1e-3, 1e-4, 1e-4, 1e-5)).forall { case (b, t) => b <= t })
  }

  it should "cap single constants and products where that makes the design cheaper, and " +
    "keep the per-kind fit where not" in {
      val shared = reducerload.config.LoadParams.shared
      val joint3 = shared.arm
      assert(!joint3.fracBitLimits.isEmpty, "the shared preset's fit caps no node")
      TargetErrorSpec.checkNodes(joint3, shared.targetError, "preset shared")
      // Capped nodes mix widths; in the UR5's 64-clock memory schedule that splits a multiplier class, so the
      // fit keeps the kinds' bits.
      val memory = Compiler.arm(
        ur5.copy(
          targetError = Seq(1e-3),
          schedule = ScheduleRequest(Some(64), storage = Some(Storage.Memory))
        )
      )
      TargetErrorSpec.checkNodes(memory, Seq.fill(memory.chain.size)(1e-3), "ur5 memory ii64")
    }

  it should "refuse a target the sin/cos unit cannot reach, and a wrong number of targets" in {
    val e = intercept[IllegalArgumentException](Compiler.arm(ur5.copy(targetError = Seq(1e-12))))
    assert(
      e.getMessage.contains("numeric.target-error") && e.getMessage.contains("cordic.output-bits"),
      e.getMessage
    )
    val n = intercept[IllegalArgumentException](Compiler.arm(ur5.copy(targetError = Seq(1e-3, 1e-3))))
    assert(n.getMessage.contains("numeric.target-error gives 2 values"), n.getMessage)
  }
}

object TargetErrorSpec {

  /**
   * `p` meets its targets and costs no more than the other fit: with per-node caps, no capped-able node
   * (constant or product) can lose one more bit, and the kinds' fit alone is not cheaper; without, the
   * per-node caps would not be cheaper.
   */
  def checkNodes(p: ArmParams, targets: Seq[Double], label: String): Unit = {
    def under(limits: FracBitLimits) =
      scala.util.Try(new Analysis(p.graph, p.numerics, p.rangeHints, limits)).toOption
    def meets(a: Analysis) = a.outputs.map(_.errorBound).zip(targets).forall { case (b, t) => b <= t }
    assert(meets(p.analysis), s"$label: bounds ${p.errorBounds} miss $targets")
    val alternative =
      if (p.fracBitLimits.isEmpty)
        p.copy(fracBitLimits = TargetFit.narrowedNodes(p.analysis, l => under(l).filter(meets)))
      else p.copy(fracBitLimits = FracBitLimits.none)
    assert(
      Ordering[(Int, Int, Int)].lteq(TargetFit.cost(p), TargetFit.cost(alternative)),
      s"$label: the fit chose cost ${TargetFit.cost(p)} over ${TargetFit.cost(alternative)}"
    )
    if (!p.fracBitLimits.isEmpty) p.graph.ids.foreach { id =>
      val bits = p.analysis(id).format.fracBits
      val cappable = p.graph(id) match { case Op.Const(_) | Op.Mul(_, _) => bits > 0; case _ => false }
      if (cappable) under(p.fracBitLimits.capped(id, bits - 1)).foreach { a =>
        assert(
          !meets(a) || a(id).raw.contains(BigInt(0)),
          s"$label: ${p.graph.describe(id)} can lose a fraction bit and still meet the target"
        )
      }
    }
    println(
      s"[target] $label: ${p.fracBitLimits.byNode.size} node(s) capped below their kind; cost (blocks, " +
        s"units, bits) ${TargetFit.cost(p)}, the other fit ${TargetFit.cost(alternative)}"
    )
  }
}
