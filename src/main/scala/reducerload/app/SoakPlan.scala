package reducerload.app

import reducerload.arm.{ArmOutputCodes, ArmParams}
import reducerload.graph.SampleCodes
import reducerload.monitor.MonitorParams
import reducerload.sim.replay.ArmReplay
import reducerload.sim.rtl.ClockStimulus

import scala.collection.mutable
import scala.util.Random

/** How often the soak does each thing it does at random. */
final case class SoakRates(
    samples: Int,
    resets: Int,
    bubbleOdds: Int = 8,
    outOfRangeOdds: Int = 16,
    snapshotOdds: Int = 1500,
    clearOdds: Int = 4000,
    readOdds: Int = 200
) {
  require(samples >= 1, s"soak: at least one sample, got $samples")
  require(resets >= 0, s"soak: resets must be >= 0, got $resets")
  Seq(bubbleOdds, outOfRangeOdds, snapshotOdds, clearOdds, readOdds).foreach(o =>
    require(o >= 1, s"soak: odds of 1 in $o")
  )
}

/**
 * A soak's seeded stimulus, in plain Scala (no simulator): the sample codes (some with a velocity or
 * acceleration beyond its declared range), the clock each becomes available (bubbles of 1 to 2 intervals
 * between some; otherwise one interval apart, so the harness holds each valid until the design takes it),
 * resets at random clocks, and with a monitor, snapshots, clears and single-word reads at random clocks and a
 * whole-bank read after every snapshot and at the end.
 */
final class SoakPlan private (
    val p: ArmParams,
    val monitor: Option[MonitorParams],
    val seed: Long,
    codes: Array[Long],
    val offerCycles: Array[Long],
    eventCycles: Array[Long],
    eventWords: Array[Long],
    val cycles: Long
) {
  private val joints = p.chain.size
  private val replay = new ArmReplay(p, monitor)

  def samples: Int = offerCycles.length

  /** Sample `k`'s codes. */
  def sample(k: Int): SampleCodes = {
    def at(part: Int) = (0 until joints).map(j => BigInt(codes(k * 3 * joints + part * joints + j)))
    SampleCodes(at(0), at(1), at(2))
  }

  /** The bit-accurate model's output for sample `k` (the long-arithmetic model where it applies). */
  def expected(k: Int): ArmOutputCodes = replay.evaluate(sample(k))

  /** The harness's input values for every sample, in order. */
  def inputs: Iterator[Seq[BigInt]] = Iterator.range(0, samples).map(k => replay.harnessValues(sample(k)))

  def events: Iterator[ClockStimulus] =
    eventCycles.indices.iterator.map(i => ClockStimulus.fromWord(eventCycles(i), eventWords(i)))

  private def count(f: ClockStimulus => Boolean) = events.count(f).toLong
  def resets: Long = count(_.reset)
  def snapshots: Long = count(_.snapshot)
  def clears: Long = count(_.clear)
  def reads: Long = count(_.read.nonEmpty)
}

object SoakPlan {

  /** Clocks after the last offer before the closing snapshot: every held sample taken and out. */
  private def settle(p: ArmParams): Long = 4L * p.schedule.clocksPerSample + p.latency + 8

  def apply(p: ArmParams, monitor: Option[MonitorParams], rates: SoakRates, seed: Long): SoakPlan = {
    val rng = new Random(seed)
    val replay = new ArmReplay(p, monitor)
    val n = p.numerics
    val joints = p.chain.size
    require(n.angleBits <= 62, s"soak: ${n.angleBits}-bit angle codes do not fit a long")
    val interval = p.schedule.clocksPerSample
    val codes = new Array[Long](rates.samples * 3 * joints)
    val offers = new Array[Long](rates.samples)
    // Future events by clock, flag words OR-ed; flushed in order as the offers pass them.
    val pending = mutable.TreeMap.empty[Long, Long]
    val (eventCycles, eventWords) = (mutable.ArrayBuilder.make[Long], mutable.ArrayBuilder.make[Long])
    def add(cycle: Long, word: Long): Unit = pending(cycle) = pending.getOrElse(cycle, 0L) | word
    def flushBefore(cycle: Long): Unit =
      while (pending.nonEmpty && pending.head._1 < cycle) {
        val (c, w) = pending.head
        pending -= c
        eventCycles += c; eventWords += w
      }
    def read(cycle: Long, address: Int) = add(cycle, ClockStimulus(cycle, read = Some(address)).word)
    val word = ClockStimulus(0, snapshot = true).word
    def snapshotAt(cycle: Long): Unit = monitor.foreach { m =>
      add(cycle, word)
      (0 until m.registerMap.words).foreach(k => read(cycle + m.snapshotLatency + k, k))
    }
    // Resets before random samples, somewhere in the interval before the sample's offer.
    val resetBefore = Seq.fill(rates.resets)(rng.nextInt(rates.samples)).toSet
    def within(limit: Double) = (2 * rng.nextDouble() - 1) * limit
    var t = 0L
    (0 until rates.samples).foreach { k =>
      if (rng.nextInt(rates.bubbleOdds) == 0) t += 1 + rng.nextInt(2 * interval)
      if (resetBefore(k)) { add(t, ClockStimulus(t, reset = true).word); t += 1 + rng.nextInt(interval) }
      val q = IndexedSeq.fill(joints)(rng.nextDouble() * 8 - 4)
      val qd = Array.tabulate(joints)(j => within(n.velocityLimits(j)))
      val qdd = Array.tabulate(joints)(j => within(n.accelerationLimits(j)))
      if (rng.nextInt(rates.outOfRangeOdds) == 0) {
        val j = rng.nextInt(joints)
        if (rng.nextBoolean()) qd(j) = 1.5 * n.velocityLimits(j) * (if (qd(j) < 0) -1 else 1)
        else qdd(j) = 1.5 * n.accelerationLimits(j) * (if (qdd(j) < 0) -1 else 1)
      }
      val s = replay.encode(q ++ qd ++ qdd)
      (s.angles ++ s.velocities ++ s.accelerations).zipWithIndex.foreach { case (v, i) =>
        codes(k * 3 * joints + i) = v.toLong
      }
      flushBefore(t)
      add(t, ClockStimulus(t, offer = true).word)
      offers(k) = t
      monitor.foreach { m =>
        def somewhere = t + rng.nextInt(interval.max(2))
        if (rng.nextInt(rates.snapshotOdds) == 0) snapshotAt(somewhere)
        if (rng.nextInt(rates.clearOdds) == 0) add(somewhere, ClockStimulus(0, clear = true).word)
        if (rng.nextInt(rates.readOdds) == 0) read(somewhere, rng.nextInt(1 << m.addressBits))
      }
      t += interval
    }
    // The closing snapshot, once every sample has left the datapath; its bank read whole.
    val last = t + settle(p)
    snapshotAt(last)
    val end = pending.lastOption.map(_._1).getOrElse(0L).max(last) + 2
    flushBefore(end)
    new SoakPlan(p, monitor, seed, codes, offers, eventCycles.result(), eventWords.result(), end)
  }
}
