package reducerload.monitor

import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.testutil.{Seeds, SimBackend}

import scala.collection.mutable.ArrayBuffer
import scala.util.Random
import reducerload.testutil.SimBackend.multiplierImpl // the JVM simulator builds the multipliers' Chisel twin

/**
 * RTL simulations of ReducerMonitor, two designs (one Verilator build each):
 *   - a 3-joint monitor on a long seeded stream with bubbles, snapshots and clears at random times (some in
 *     the same cycle), the register bank read while samples keep coming: every bank equal to the model's word
 *     for word, `snapshotDone` exactly `snapshotLatency` cycles after each pulse, the limit counters exact at
 *     the thresholds, and every snapshot's figures against the double reference (histogram and counts exact,
 *     damage sum and T_av within the derived bound);
 *   - the top bits of the 20-year widths: accumulators preset to the worst case of the sample budget minus a
 *     few thousand samples, then driven at the extremes of the declared ranges.
 */
class ReducerMonitorSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "ReducerMonitor"

  /** Cycles of samples (with bubbles), snapshots, clears and the bank reads after each snapshot. */
  private def schedule(
      p: MonitorParams,
      prelude: IndexedSeq[MonitorSampleCodes],
      samples: IndexedSeq[MonitorSampleCodes],
      rng: Random,
      bubble: Double,
      snapshotOdds: Int,
      clearOdds: Int
  ): (IndexedSeq[DriveCycle], IndexedSeq[Int]) = {
    val out = ArrayBuffer.empty[DriveCycle]
    val snapshots = ArrayBuffer.empty[Int]
    val reads = scala.collection.mutable.Map.empty[Int, Int]
    val words = p.registerMap.words
    def snapshotAt(t: Int): Unit = {
      snapshots += t
      (0 until words).foreach(k => reads(t + p.snapshotLatency + k) = k)
    }
    def free(t: Int) = snapshots.lastOption.forall(s => t >= s + p.snapshotLatency + words)
    // Prelude: clear with the first sample (it is the first of the period), snapshot with a sample
    // that must not be in it, then snapshot-and-clear with a sample that starts the next period.
    prelude.indices.foreach(i => out += DriveCycle(MonitorCycle(Some(prelude(i)), clear = i == 0)))
    snapshotAt(out.size); out += DriveCycle(MonitorCycle(Some(samples.head), snapshot = true, clear = true))
    val rest = samples.tail.iterator
    while (rest.hasNext || !free(out.size)) {
      val t = out.size
      val sample = if (rest.hasNext && rng.nextDouble() >= bubble) Some(rest.next()) else None
      val snap = free(t) && snapshots.size < 2 + t / 50 && rng.nextInt(snapshotOdds) == 0
      if (snap) snapshotAt(t)
      val clear = rng.nextInt(clearOdds) == 0 || (snap && rng.nextInt(3) == 0)
      out += DriveCycle(MonitorCycle(sample, snapshot = snap, clear = clear), reads.get(t))
    }
    snapshotAt(out.size); out += DriveCycle(MonitorCycle(None, snapshot = true))
    while (reads.contains(out.size) || out.size < snapshots.last + p.snapshotLatency + 1)
      out += DriveCycle(MonitorCycle(None), reads.get(out.size))
    (out.toIndexedSeq, snapshots.toIndexedSeq)
  }

  /** The model's bank after each snapshot cycle, and the samples of the period each snapshot closes. */
  private def expected(p: MonitorParams, drive: IndexedSeq[DriveCycle], snapshots: Set[Int]) = {
    val model = new MonitorModel(p)
    val banks = ArrayBuffer.empty[(MonitorSnapshot, IndexedSeq[MonitorSampleCodes])]
    drive.indices.foldLeft((model.initial, Vector.empty[MonitorSampleCodes])) { case ((state, period), t) =>
      val c = drive(t).cycle
      val next = model.step(state, c)
      if (snapshots(t)) banks += (next.shadow -> period)
      val started = if (c.clear) Vector.empty else period
      (next, started ++ c.sample.toSeq)
    }
    banks.toIndexedSeq
  }

  private def readBanks(
      p: MonitorParams,
      drive: IndexedSeq[DriveCycle],
      observed: IndexedSeq[ObservedCycle],
      snapshots: Seq[Int]
  ) =
    snapshots.map(t =>
      (0 until p.registerMap.words).map(k => observed(t + p.snapshotLatency + k).readData.get)
    )

  private def describeDifference(
      p: MonitorParams,
      hw: IndexedSeq[BigInt],
      model: IndexedSeq[BigInt]
  ): String = {
    val (h, m) = (p.registerMap.decode(hw), p.registerMap.decode(model))
    p.registerMap.entries
      .filter(e => h(e.key) != m(e.key))
      .map(e => s"${e.name}: RTL ${h(e.key)}, model ${m(e.key)}")
      .mkString("; ")
  }

  /** Every figure of the snapshot against the double reference over the same samples. */
  private def checkAgainstReference(
      p: MonitorParams,
      snap: MonitorSnapshot,
      period: Seq[MonitorSampleCodes],
      label: String
  ): Double = {
    val hw = MonitorSummary.fromSnapshot(p, snap)
    val ref = MonitorReference.summarize(p, period.map(MonitorReference.values(p, _)))
    (0 until p.joints).map { j =>
      val (h, r, s) = (hw(j), ref(j), snap.joints(j))
      val where = s"$label ${h.name}"
      assert(h.samples == r.samples && h.outOfRangeSamples == r.outOfRangeSamples, s"$where: sample counts")
      assert(
        h.peakNm == r.peakNm && h.minNm == r.minNm,
        s"$where: peak ${h.peakNm} / ${r.peakNm}, min ${h.minNm} / ${r.minNm}"
      )
      assert(
        h.repeatedPeakSamples == r.repeatedPeakSamples,
        s"$where: repeated-peak samples ${h.repeatedPeakSamples} vs ${r.repeatedPeakSamples}"
      )
      assert(
        h.momentaryPeakEvents == r.momentaryPeakEvents,
        s"$where: momentary events ${h.momentaryPeakEvents} vs ${r.momentaryPeakEvents}"
      )
      assert(
        h.lastEventPeakNm == r.lastEventPeakNm && h.lastEventSpeedRadS == r.lastEventSpeedRadS &&
          h.lastEventDurationSamples == r.lastEventDurationSamples,
        s"$where: last event $h vs $r"
      )
      assert(h.histogram == r.histogram, s"$where: histogram ${h.histogram} vs ${r.histogram}")
      val damageBound = MonitorSummary.damageSumBound(p, j, h.damageSum, r.speedSumRad)
      assert(
        math.abs(h.damageSum - r.damageSum) <= damageBound,
        s"$where: damage ${h.damageSum} vs ${r.damageSum}, bound $damageBound"
      )
      assert(math.abs(h.speedSumRad - r.speedSumRad) <= 1e-9 * (1 + r.speedSumRad), s"$where: speed sum")
      (h.avgTorqueNm, r.avgTorqueNm, MonitorSummary.avgTorqueBound(p, j, s)) match {
        case (Some(a), Some(b), Some(bound)) =>
          assert(math.abs(a - b) <= bound, s"$where: T_av $a vs $b, bound $bound")
          math.abs(a - b) / bound
        case (None, None, None) => 0.0
        case other              => fail(s"$where: T_av presence differs: $other")
      }
    }.max
  }

  it should "equal the model bit for bit on a long seeded stream with snapshots and clears, exact at the " +
    "thresholds and within the derived bound of the reference" in {
      val p = MonitorStimulus.threeJoints
      val rng = new Random(Seeds("monitor-stream", 1301L))
      val n = SimBackend.scale(20000)
      val prelude = MonitorStimulus.thresholdSamples(p, rng)
      val (drive, snapshots) = schedule(
        p,
        prelude,
        MonitorStimulus.samples(p, n, rng),
        rng,
        bubble = 0.2,
        snapshotOdds = 600,
        clearOdds = 2500
      )
      val banks = expected(p, drive, snapshots.toSet)
      println(
        s"[monitor] ${p.joints} joints, $n random samples, ${drive.size} " +
          s"cycles, ${snapshots.size} snapshots, ${drive.count(_.cycle.clear)} clears, update stage " +
          s"${p.updateStage}, bank ${p.registerMap.words} words"
      )

      test(new ReducerMonitor(p)).withAnnotations(SimBackend.annotations) { dut =>
        val observed = MonitorDriver.run(dut, drive)
        val done = observed.indices.filter(observed(_).snapshotDone)
        assert(
          done == snapshots.map(_ + p.snapshotLatency),
          s"snapshotDone at $done, expected ${snapshots.map(_ + p.snapshotLatency)}"
        )
        val hwBanks = readBanks(p, drive, observed, snapshots)
        hwBanks.zip(banks).zipWithIndex.foreach { case ((hw, (model, _)), k) =>
          val m = model.bank(p)
          assert(hw == m, s"snapshot $k (cycle ${snapshots(k)}): ${describeDifference(p, hw, m)}")
        }

        // The prelude's snapshot: limit counters at just below, at and just above T_R and T_M ("above" is >).
        val first = MonitorSnapshot.fromBank(p, hwBanks.head)
        (0 until p.joints).foreach { j =>
          val s = first.joints(j)
          val name = p.jointNames(j)
          assert(
            s.samples == prelude.size,
            s"$name: the sample in the snapshot's own cycle must not be in it"
          )
          assert(
            s.repeatedPeakSamples == 8,
            s"$name: samples above T_R ${s.repeatedPeakSamples}, expected 8 (r+1 twice, m-1 .. m+2, m, m+1)"
          )
          assert(
            s.momentaryPeakEvents == 2 && s.lastEventDuration == 1 && s.lastEventPeak == p.momentaryPeakCode(
              j
            ) + 1,
            s"$name: events ${s.momentaryPeakEvents}, last duration " +
              s"${s.lastEventDuration}, last peak ${s.lastEventPeak}"
          )
          assert(s.repeatedPeakSeen && s.momentaryPeakSeen && s.inEvent, s"$name: flags ${s.flags}")
          // At the N·m level: the code at T_R is not above it, the next one is (the reference agrees below).
          val f = p.torqueFormats(j)
          assert(
            f.toDouble(p.repeatedPeakCode(j)) <= p.repeatedPeakNm(j) && f.toDouble(
              p.repeatedPeakCode(j) + 1
            ) > p.repeatedPeakNm(j)
          )
        }
        // The prelude's snapshot-and-clear: the sample of that cycle is the first of the next period.
        if (!drive.slice(snapshots(0) + 1, snapshots(1) + 1).exists(_.cycle.clear))
          assert(
            banks(1)._2.head == drive(snapshots.head).cycle.sample.get && banks(1)._1.joints.head.samples >= 1
          )

        val worst = hwBanks
          .zip(banks)
          .zipWithIndex
          .map { case ((hw, (_, period)), k) =>
            checkAgainstReference(p, MonitorSnapshot.fromBank(p, hw), period, s"snapshot $k")
          }
          .max
        println(
          f"[monitor] ${snapshots.size} banks bit-exact with the model; every snapshot " +
            f"within the reference's bounds (worst T_av error ${worst * 100}%.1f%% of its bound)"
        )
      }
    }

  it should "hold the sample budget in every accumulator: preset near the 20-year worst " +
    "case, driven at the range extremes" in {
      val headroom = 3000
      val base = MonitorStimulus.threeJoints
      val p =
        base.copy(testStartAfterSamples = Some(base.sampleBudget - headroom), histogramCounterBits = Some(10))
      val rng = new Random(Seeds("monitor-overflow", 1302L))
      // Worst-case samples: |tau| and |qd| at their maxima (the most negative codes too, which saturate
      // to the same magnitudes), all above T_M so the preset event goes on, none out of range.
      val extremes = IndexedSeq.tabulate(headroom) { i =>
        MonitorSampleCodes(
          p.torqueFormats
            .map(f => if (i % 3 == 1) f.minRaw else if (i % 3 == 2) -f.maxRaw else f.maxRaw)
            .toIndexedSeq,
          p.velocityFormats.map(f => if (rng.nextBoolean()) f.minRaw else f.maxRaw).toIndexedSeq,
          IndexedSeq.fill(p.joints)(false)
        )
      }
      val drive = (extremes.map(s => DriveCycle(MonitorCycle(Some(s)))) :+ DriveCycle(
        MonitorCycle(None, snapshot = true)
      )) ++
        (0 until p.snapshotLatency - 1 + p.registerMap.words).map(k =>
          DriveCycle(
            MonitorCycle(None),
            if (k >= p.snapshotLatency - 1) Some(k - p.snapshotLatency + 1) else None
          )
        )
      val snapAt = extremes.size
      val model = banksOf(p, drive, snapAt)

      test(new ReducerMonitor(p)).withAnnotations(SimBackend.annotations) { dut =>
        val observed = MonitorDriver.run(dut, drive)
        val hw = (0 until p.registerMap.words).map(k => observed(snapAt + p.snapshotLatency + k).readData.get)
        assert(hw == model.bank(p), describeDifference(p, hw, model.bank(p)))
        val snap = MonitorSnapshot.fromBank(p, hw)
        (0 until p.joints).foreach { j =>
          p.provenAccumulators.filterNot(_ == JointField.OutOfRangeSamples).foreach { f =>
            val (value, w) = (snap.joints(j).field(f), p.accumulatorBits(j, f))
            val expectedTop =
              if (f == JointField.MomentaryPeakEvents) p.clearValue(j, f)
              else p.maxIncrement(j, f) * p.sampleBudget
            assert(
              value == expectedTop,
              s"${p.jointNames(j)}.${f.name}: $value, expected the 20-year worst case $expectedTop"
            )
            assert(
              value.testBit(w - 1) && value.bitLength == w,
              s"${p.jointNames(j)}.${f.name}: top bit ${w - 1} of $w not reached ($value)"
            )
            println(
              s"[monitor] ${p.jointNames(j)}.${f.name}: $value after the worst-case budget " +
                s"of ${p.sampleBudget} samples, top bit ${w - 1} set, below 2^$w"
            )
          }
          assert(
            snap.joints(j).histogramSaturated && snap.joints(j).histogram.last == p.histogramMax,
            s"${p.jointNames(j)}: the 10-bit histogram counter should saturate " +
              s"at ${p.histogramMax} and flag it"
          )
        }
      }
      // One more worst-case sample breaks the budget: the model (which checks every accumulator) refuses it.
      val m = new MonitorModel(p)
      val full = extremes.foldLeft(m.initial)((s, x) => m.step(s, MonitorCycle(Some(x))))
      val beyond = intercept[IllegalArgumentException](m.step(full, MonitorCycle(Some(extremes.head))))
      assert(
        beyond.getMessage.contains("exceeds its proven") || beyond.getMessage.contains("sample budget"),
        beyond.getMessage
      )
    }

  private def banksOf(p: MonitorParams, drive: IndexedSeq[DriveCycle], snapAt: Int): MonitorSnapshot =
    expected(p, drive, Set(snapAt)).head._1
}
