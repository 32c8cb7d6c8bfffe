package reducerload.app

import reducerload.arm.ArmOutputCodes
import reducerload.monitor.{MonitorCycle, MonitorModel, MonitorModelState, MonitorSnapshot, MonitoredArm}
import reducerload.sim.rtl.{ArmHarnessPorts, ClockStimulus, Observed}

import scala.collection.mutable

/**
 * Checks a soak run against the bit-accurate models, in plain Scala (no simulator), in constant memory: feed
 * it what the design did ([[observe]], in clock order), then [[finish]].
 *
 *   - Taking: sample k is taken after it was offered and after sample k - 1, never in a reset clock, within
 *     one interval of the first clock it could be, and between two resets always in the same phase of the
 *     interval (the datapath's `ready`).
 *   - Outputs: the sample taken in clock a comes out in clock a + latency, equal to `expect` (the arm model),
 *     unless a reset came in clocks a + 1 to a + latency - 1; no other output.
 *   - The monitor ([[MonitorModel]] in its input clocks, which are the output clocks, fed the model's outputs
 *     as [[MonitoredArm.monitorSample]] derives them): a snapshot pulsed in clock s is in the shadow bank
 *     from clock s + snapshotLatency (and snapshotDone is high then) unless a reset came in clocks s to s +
 *     snapshotLatency - 1; a reset in clock r clears every state and drops the monitor inputs of clocks up to
 *     r (its registers, control bits included, are reset), so the bank reads as cleared from clock r + 1; a
 *     read in clock t returns the word of the bank as it is in clock t.
 */
final class SoakCheck(plan: SoakPlan, expect: Int => ArmOutputCodes) {
  private val p = plan.p
  private val latency = p.latency
  private val interval = p.schedule.clocksPerSample
  private val torques = p.graph.outputs.size

  private val events = plan.events.buffered
  private final class InFlight(val arrival: Long, val sample: Int) {
    lazy val out: ArmOutputCodes = expect(sample)
    var observed = false
  }
  private val inFlight = mutable.Queue.empty[InFlight]

  // The monitor: model state, bank versions (visible from a clock), expected snapshotDone clocks.
  private val monitor = plan.monitor.map(m => (m, new MonitorModel(m)))
  private var state: Option[MonitorModelState] = monitor.map(_._2.initial)
  private val versions = mutable.Queue.empty[(Long, MonitorSnapshot)]
  private var bank: Option[(MonitorSnapshot, IndexedSeq[BigInt])] =
    monitor.map { case (m, model) => (model.initial.shadow, model.initial.shadow.bank(m)) }
  private val dones = mutable.Queue.empty[Long]
  private var lastRead = -1L // the clock of the last read data seen

  private var taken = 0
  private var lastTaken = -1L
  private var lastReset = -1L
  private var phase: Option[Long] = None // clock of the first take since the last reset, mod interval
  private var now = 0L

  private var mismatchCount = 0L
  private val firstMismatches = mutable.ArrayBuffer.empty[String]
  var outputs = 0L
  var flagged = 0L
  var readsChecked = 0L
  var snapshotsSeen = 0L

  def mismatches: Long = mismatchCount
  def examples: Seq[String] = firstMismatches.toSeq
  def samplesTaken: Int = taken

  private def mismatch(cycle: Long, what: => String): Unit = {
    mismatchCount += 1
    if (firstMismatches.size < 10) firstMismatches += s"clock $cycle: $what"
  }

  /** Process every clock before `t` that has something to model. */
  private def advanceTo(t: Long): Unit = {
    var more = true
    while (more) {
      val next = Seq(
        events.headOption.map(_.cycle),
        inFlight.headOption.map(_.arrival),
        dones.headOption
      ).flatten.minOption
      next match {
        case Some(c) if c < t => clock(c)
        case _                => more = false
      }
    }
    now = t
  }

  /** Everything of clock `c`, in the RTL's order. */
  private def clock(c: Long): Unit = {
    val e = if (events.headOption.exists(_.cycle == c)) events.next() else ClockStimulus(c)
    val arrival = if (inFlight.headOption.exists(_.arrival == c)) Some(inFlight.dequeue()) else None
    arrival.foreach(a =>
      if (!a.observed) mismatch(c, s"no output for sample ${a.sample} (taken in ${c - latency})")
    )
    if (dones.headOption.contains(c)) {
      dones.dequeue(); mismatch(c, "snapshotDone low a snapshot latency after a snapshot")
    }
    e.read.foreach(a => if (lastRead != c) mismatch(c, s"no read data for address $a"))
    monitor.foreach { case (m, model) =>
      val in = arrival.map(a => MonitoredArm.monitorSample(p, plan.sample(a.sample), a.out))
      if (in.nonEmpty || e.snapshot || e.clear) {
        val next = model.step(state.get, MonitorCycle(in, e.snapshot, e.clear))
        state = Some(next)
        if (e.snapshot) {
          versions.enqueue(c + m.snapshotLatency -> next.shadow); dones.enqueue(c + m.snapshotLatency)
        }
      }
      if (e.reset) {
        state = Some(model.initial)
        versions.filterInPlace(_._1 <= c)
        dones.filterInPlace(_ <= c)
        versions.enqueue(c + 1 -> model.initial.shadow)
      }
    }
    if (e.reset) {
      inFlight.filterInPlace(_.arrival <= c)
      lastReset = c
      phase = None
    }
  }

  /** The bank as it is in clock `t`. */
  private def bankAt(t: Long): IndexedSeq[BigInt] = {
    val m = monitor.get._1
    while (versions.headOption.exists(_._1 <= t)) {
      val (_, snap) = versions.dequeue()
      bank = Some(snap -> snap.bank(m))
    }
    bank.get._2
  }

  def observe(o: Observed): Unit = {
    if (o.cycle < now) mismatch(o.cycle, s"$o out of clock order (after clock $now)")
    advanceTo(o.cycle)
    val t = o.cycle
    o match {
      case Observed.Output(_, values) =>
        outputs += 1
        inFlight.headOption.filter(_.arrival == t) match {
          case Some(a) =>
            a.observed = true
            val got = ArmHarnessPorts.codes(values, torques)
            if (got.outOfRange.exists(identity)) flagged += 1
            if (got != a.out) mismatch(t, s"sample ${a.sample}: expected ${a.out}, observed $got")
          case None => mismatch(t, s"an output no sample was due for: ${values.mkString(", ")}")
        }
      case Observed.Taken(_) =>
        val k = taken
        taken += 1
        if (k >= plan.samples) mismatch(t, s"sample $k taken, only ${plan.samples} were offered")
        else {
          val from = plan.offerCycles(k).max(lastTaken + 1).max(lastReset + 1)
          if (t < plan.offerCycles(k))
            mismatch(t, s"sample $k taken before its offer in ${plan.offerCycles(k)}")
          else if (events.headOption.exists(e => e.cycle == t && e.reset))
            mismatch(t, s"sample $k taken in reset")
          else if (t - from >= interval)
            mismatch(t, s"sample $k held ${t - from} clocks (interval $interval)")
          else if (phase.exists(_ != t % interval)) mismatch(t, s"sample $k taken out of phase")
          phase = Some(t % interval)
          lastTaken = t
          inFlight.enqueue(new InFlight(t + latency, k))
        }
      case Observed.SnapshotDone(_) =>
        if (dones.headOption.contains(t)) { dones.dequeue(); snapshotsSeen += 1 }
        else mismatch(t, "snapshotDone high with no snapshot due")
      case Observed.ReadData(_, value) =>
        val address = events.headOption.filter(_.cycle == t).flatMap(_.read)
        address match {
          case None => mismatch(t, "read data for a clock with no read")
          case Some(a) =>
            lastRead = t
            readsChecked += 1
            val words = bankAt(t)
            val want = if (a < words.size) words(a) else BigInt(0)
            if (BigInt(value) != want) {
              val name = monitor.get._1.registerMap.entries.filter(_.address <= a).lastOption.map(_.name)
              mismatch(t, s"read of word $a (${name.getOrElse("-")}): expected $want, observed $value")
            }
        }
    }
  }

  /** After the last observation: every sample taken, every output, done and read seen. */
  def finish(): Unit = {
    advanceTo(plan.cycles + latency + 1)
    if (taken < plan.samples) mismatch(plan.cycles, s"${plan.samples - taken} samples never taken")
  }
}
