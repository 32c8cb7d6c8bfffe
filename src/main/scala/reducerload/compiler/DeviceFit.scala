package reducerload.compiler

import reducerload.arm.ArmParams
import reducerload.config.{DeviceTarget, LoadParams}
import reducerload.graph.{Schedule, ScheduleRequest, Storage}
import reducerload.monitor.MonitorConfig
import reducerload.util.Warning

/**
 * A design scheduled for the fit, with its predicted resources (the monitor's included); `refinedAgain` when
 * the fit refined it with more steps than asked for ([[DeviceFit.closeMargin]]).
 */
final case class Candidate(arm: ArmParams, resources: Resources, refinedAgain: Boolean = false) {
  def clocksPerSample: Int = arm.schedule.clocksPerSample
  def storage: Storage = arm.scheduleRequest.stored
  def describe: String =
    s"$clocksPerSample clock${if (clocksPerSample == 1) "" else "s"} per sample, ${storage.name} storage" +
      (if (storage == Storage.Registers && arm.memoryDelayMinCycles == 0) ", no block-RAM delays" else "") +
      refinement

  /** How the fit refined it, when beyond what was asked. */
  def refinement: String =
    if (refinedAgain) s", refined with ${arm.scheduleRequest.refinement} steps per operation" else ""
}

/**
 * The design a compilation ends with and how it relates to the device: `chosen` when the fit picked the
 * interval or the storage (with the runner-up it beat), else as requested; `warnings` for every resource an
 * explicit request takes beyond the device.
 */
final case class Fitted(
    target: DeviceTarget,
    design: Candidate,
    chosen: Boolean,
    passedOver: Option[Candidate],
    warnings: Seq[Warning]
) {
  private def grouped(n: Int) = String.format(java.util.Locale.ROOT, "%,d", Int.box(n))

  /** The `emit` line: what was chosen (or built) and its use of the device. */
  def line: String = {
    val d = target.part
    val r = design.resources
    val use = s"${r.multiplierBlocks}/${d.multiplierBlocks} multiplier blocks, " +
      s"${r.memoryBlocks}/${d.memoryBlocks} ${d.family.memoryBlock}, " +
      s"~${grouped(r.logicElements)}/${grouped(d.logicElements)} ${d.family.logicCell} predicted"
    val why = passedOver.fold("") { c =>
      val over = DeviceFit.exceeded(target, c)
      s" (${c.storage.name} at ${c.clocksPerSample} clocks${c.refinement}: ${if (over.isEmpty) "over the multiplier budget"
        else over})"
    }
    if (chosen) s"device $d: chose ${design.describe}: $use$why"
    else s"device $d: ${design.describe} as requested: $use"
  }
}

/**
 * The device fit (`device.*`): the schedule settings left `auto` are chosen so that the design fits the
 * device: the fewest clocks per sample (then the lower latency), registers or block-RAM storage. Fits: 18x18
 * blocks within the device's (and `schedule.max-multipliers`), memory blocks within its, predicted logic
 * cells within `device.max-logic-fraction` of its. Separate from the schedule: it only picks the request.
 */
object DeviceFit {

  /** A count with thousands separators, the same in every locale. */
  def grouped(n: Int): String = String.format(java.util.Locale.ROOT, "%,d", Int.box(n))

  /**
   * Intervals tried above the fewest the blocks allow: a design's resources fall as the interval grows, so
   * the first that fits is found by doubling, then halving the step.
   */
  val largestInterval: Int = 1024

  /**
   * How far beyond the logic budget a registers candidate refined with a tenth of its steps may be predicted
   * and still be refined fully: the full refinement lowered the prediction by 3.7-7.8 % over the Panda's
   * intervals 34..97 (a candidate passed over wrongly costs a slower design, never a wrong one).
   */
  val screenMargin: Double = 1.10

  /**
   * A registers candidate predicted over the logic budget by its logic alone, by at most this fraction, is
   * refined again with `closeRefinementFactor` times the steps, and that result is the fit's word on its
   * interval: the annealing's prediction moves by a few percent with its steps (docs/device.md), so a design
   * within that noise of the budget is not given up on one run of it.
   */
  val closeMargin: Double = 1.05

  /** How many times the asked refinement steps a candidate within `closeMargin` is refined with again. */
  val closeRefinementFactor: Int = 5

  private def blocksWithin(t: DeviceTarget, budget: Int)(c: Candidate): Boolean =
    c.resources.multiplierBlocks <= math.min(budget, t.part.multiplierBlocks)

  private def fitsWith(t: DeviceTarget, budget: Int)(c: Candidate): Boolean =
    blocksWithin(t, budget)(c) && c.resources.memoryBlocks <= t.part.memoryBlocks &&
      c.resources.logicElements <= t.logicBudget

  /** The design for `p`: as requested when every schedule choice is explicit, else the device fit's. */
  def apply(p: LoadParams, base: ArmParams): Fitted = {
    val request = p.schedule
    val target = p.device
    // The graph and its analysis first: their refusals are the user's, not a resource's.
    base.analysis
    val family = target.part.family
    val monitorCost: Option[Resources] =
      if (!p.monitor.enabled) None
      else {
        val m = MonitorConfig(base, p.monitor)
        Some(ResourceModel.ofMonitor(base, m, family))
      }
    def candidate(r: ScheduleRequest, on: ArmParams = base): Candidate = {
      val a = on.copy(scheduleRequest = r)
      Candidate(a, monitorCost.foldLeft(ResourceModel.of(a, family))(_ + _))
    }
    // The same datapath with every held value in registers (datapath.memory-delay-min-cycles = 0).
    val noDelays = base.copy(datapath = base.datapath.copy(memoryDelayMinCycles = 0))
    val monitorBlocks = monitorCost.fold(0)(_.multiplierBlocks)
    val budget = request.maxMultipliers.getOrElse(target.part.multiplierBlocks - monitorBlocks)
    val fits = fitsWith(target, budget + monitorBlocks) _
    val storages: Seq[Storage] = request.storage match {
      case Some(s) => Seq(s)
      case None    => Storage.all
    }
    request.clocksPerSample match {
      case Some(ii) =>
        // Memory needs 2 clocks or more; asked for at 1, its schedule refuses it with the numbers.
        val usable = storages.filter(s => ii >= 2 || s == Storage.Registers) match {
          case Seq() => storages
          case some  => some
        }
        val first = candidate(request.copy(storage = Some(usable.head)))
        // Another storage only when the first does not fit and it does (it may not schedule at all).
        val chosen =
          if (fits(first)) None
          else
            usable.tail.iterator
              .map(s => scala.util.Try(candidate(request.copy(storage = Some(s)))).toOption)
              .collectFirst { case Some(c) if fits(c) => c }
        val design = chosen.getOrElse(first)
        Fitted(target, design, chosen.isDefined, chosen.map(_ => first), over(target, design))
      case None =>
        // Over the budget by its logic only, and by no more than the refinement's noise.
        def closeToFitting(c: Candidate): Boolean =
          request.refinement > 0 && blocksWithin(target, budget + monitorBlocks)(c) &&
            c.resources.memoryBlocks <= target.part.memoryBlocks &&
            c.resources.logicElements <= target.logicBudget * closeMargin
        // Registers storage keeps long stretches of held values in block RAM (HeldTaps); where only the M9K
        // they take keep a design off the device, its held values stay in registers (more LEs, which the fit
        // has: on the UR5 this is 18 clocks per sample where the delays need 19).
        // Each interval and storage once: the search, the runner-up and the screen below ask again.
        val tried = scala.collection.mutable.Map.empty[(Storage, Int), Candidate]
        def at(s: Storage)(ii: Int): Candidate = tried.getOrElseUpdate(
          (s, ii), {
            val r = request.copy(clocksPerSample = Some(ii), storage = Some(s))
            val c = candidate(r)
            if (s != Storage.Registers || fits(c)) c
            else if (closeToFitting(c))
              candidate(r.copy(refinement = r.refinement * closeRefinementFactor)).copy(refinedAgain = true)
            else if (base.memoryDelayMinCycles == 0 || c.resources.memoryBlocks <= target.part.memoryBlocks)
              c
            else Some(candidate(r, noDelays)).filter(fits).getOrElse(c)
          }
        )
        // The refinement takes most of a registers candidate's time (the Panda: ~5.5 s at the default steps,
        // ~0.6 s at a tenth, whose prediction is 4-8 % more LEs): the search passes over a candidate whose
        // tenth-effort prediction is beyond the device by more than that without refining it fully.
        def screened(s: Storage)(ii: Int): Candidate =
          if (s != Storage.Registers || request.refinement < 10) at(s)(ii)
          else {
            val r = request.copy(
              clocksPerSample = Some(ii),
              storage = Some(s),
              refinement = request.refinement / 10
            )
            val quick = candidate(r)
            val hopeless = !blocksWithin(target, budget + monitorBlocks)(quick) ||
              quick.resources.logicElements > target.logicBudget * screenMargin
            if (hopeless) quick else at(s)(ii)
          }
        def leastSchedule(s: Storage): Int = new Schedule(
          base.analysis,
          request.copy(clocksPerSample = None, storage = Some(s), maxMultipliers = Some(math.max(1, budget))),
          base.cordic,
          base.multiplierLatency,
          reducerload.arm.ArmDatapath.inputCycle
        ).clocksPerSample
        // The fewest clocks the blocks allow, per storage (memory leaves each unit an eighth of its slots).
        def least(s: Storage): Option[Int] =
          scala.util
            .Try(leastSchedule(s))
            .toOption
            .map(ii => if (s == Storage.Memory) math.max(ii, 2) else ii)
        // An explicit budget below what any interval needs: the schedule's own refusal, with its numbers.
        if (request.maxMultipliers.isDefined) leastSchedule(storages.head)
        // Registers first (cheap to schedule); block RAM only below the interval registers need.
        val registers =
          if (!storages.contains(Storage.Registers)) None
          else
            least(Storage.Registers).flatMap(lo =>
              firstFitting(lo, largestInterval, screened(Storage.Registers), fits)
            )
        val memory =
          if (!storages.contains(Storage.Memory)) None
          else
            least(Storage.Memory).flatMap { lo =>
              val hi = registers.fold(largestInterval)(_.clocksPerSample)
              if (lo > hi) None else firstFitting(lo, hi, at(Storage.Memory), fits)
            }
        val found = (registers.toSeq ++ memory.toSeq).sortBy(c => (c.clocksPerSample, c.arm.latency))
        found.headOption match {
          case Some(best) =>
            val passed =
              if (best.storage == Storage.Memory && storages.contains(Storage.Registers))
                scala.util.Try(at(Storage.Registers)(best.clocksPerSample)).toOption.filterNot(fits)
              else if (best.clocksPerSample > 1)
                scala.util.Try(at(best.storage)(best.clocksPerSample - 1)).toOption.filterNot(fits)
              else None
            Fitted(target, best, chosen = true, passed, Nil)
          case None =>
            val smallest = scala.util.Try(at(storages.head)(largestInterval)).toOption
            val described = smallest.fold(s"more than $budget multiplier blocks")(c =>
              s"${c.describe}: ${needs(target, c)}"
            )
            throw new IllegalArgumentException(
              s"no design fits the device ${target.part} at any clocks per sample (the smallest, $described); " +
                "choose a larger device (device.name) or give the schedule settings explicitly"
            )
        }
    }
  }

  /**
   * The first interval from `lo` whose design fits: doubling the step until one fits (or the largest interval
   * does not), then halving it back, so a few dozen schedules at most.
   */
  private def firstFitting(
      lo: Int,
      hi: Int,
      at: Int => Candidate,
      fits: Candidate => Boolean
  ): Option[Candidate] = {
    val memo = scala.collection.mutable.Map.empty[Int, Option[Candidate]]
    def tryAt(ii: Int): Option[Candidate] =
      memo.getOrElseUpdate(ii, scala.util.Try(at(ii)).toOption.filter(fits))
    @scala.annotation.tailrec
    def grow(last: Int, step: Int): Option[(Int, Int)] = {
      val ii = math.min(lo + step, hi)
      if (tryAt(ii).isDefined) Some((last, ii))
      else if (ii >= hi) None
      else grow(ii, step * 2)
    }
    @scala.annotation.tailrec
    def narrow(failing: Int, fitting: Int): Int =
      if (fitting - failing <= 1) fitting
      else {
        val mid = (failing + fitting) / 2
        if (tryAt(mid).isDefined) narrow(failing, mid) else narrow(mid, fitting)
      }
    if (tryAt(lo).isDefined) tryAt(lo)
    else if (lo >= hi) None
    else grow(lo, 1).flatMap { case (failing, fitting) => tryAt(narrow(failing, fitting)) }
  }

  /** The resources a candidate takes beyond the device (logic: beyond the headroom). */
  def exceeded(t: DeviceTarget, c: Candidate): String = {
    val d = t.part
    val r = c.resources
    Seq(
      Option.when(r.multiplierBlocks > d.multiplierBlocks)(
        s"${r.multiplierBlocks} multiplier blocks of ${d.multiplierBlocks}"
      ),
      Option.when(r.memoryBlocks > d.memoryBlocks)(
        s"${r.memoryBlocks} ${d.family.memoryBlock} of ${d.memoryBlocks}"
      ),
      Option.when(r.logicElements > t.logicBudget)(
        s"~${grouped(r.logicElements)} ${d.family.logicCell}, over ${math.round(t.maxLogicFraction * 100)}% of the device"
      )
    ).flatten.mkString(", ")
  }

  /** What a candidate needs against the device, one resource each. */
  private def needs(t: DeviceTarget, c: Candidate): String =
    Resource.all
      .map { r =>
        s"${grouped(r.used(c.resources))}/${grouped(r.capacity(t.part))} ${r.unit(t.part)}"
      }
      .mkString(", ")

  /**
   * One warning per resource a design built as requested takes beyond the device (logic: beyond its
   * headroom).
   */
  def over(t: DeviceTarget, c: Candidate): Seq[Warning] = {
    val d = t.part
    val r = c.resources
    val where = s"device ${d.name}"
    Seq(
      Option.when(r.multiplierBlocks > d.multiplierBlocks)(
        Warning(
          where,
          s"the design (${c.describe}) uses ${r.multiplierBlocks} 18x18 multiplier blocks, the device has ${d.multiplierBlocks}"
        )
      ),
      Option.when(r.memoryBlocks > d.memoryBlocks)(
        Warning(
          where,
          s"the design (${c.describe}) uses ${r.memoryBlocks} ${d.family.memoryBlock} blocks, the device has ${d.memoryBlocks}"
        )
      ),
      Option.when(r.logicElements > t.logicBudget)(
        Warning(
          where,
          s"the design (${c.describe}) is predicted to use ~${grouped(r.logicElements)} ${d.family.logicCell}, " +
            s"over ${math.round(t.maxLogicFraction * 100)}% of the device's ${grouped(d.logicElements)} (device.max-logic-fraction)"
        )
      )
    ).flatten
  }
}
