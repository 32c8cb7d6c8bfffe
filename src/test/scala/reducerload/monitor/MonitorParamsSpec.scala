package reducerload.monitor

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.fixedpoint.FixedFormat

import java.nio.file.{Files, Paths}

/** Elaboration-time derivations: the 20-year proof, the power table's bound, the register map, refusals. */
class MonitorParamsSpec extends AnyFlatSpec {
  behavior of "MonitorParams"

  it should "prove every accumulator holds 20 years at 1 kHz and at 16 kHz (6 " +
    "joints), with no spare top bit" in {
      for (period <- Seq(1e-3, 1.0 / 16000)) {
        val p = MonitorParams.example(period)
        val expectedBudget = BigInt(math.ceil(20 * 365.25 * 86400 / period).toLong)
        assert((p.sampleBudget - expectedBudget).abs <= 1, s"budget ${p.sampleBudget} vs $expectedBudget")
        (0 until p.joints).foreach { j =>
          p.provenAccumulators.foreach { f =>
            val total = p.maxIncrement(j, f) * p.sampleBudget
            val w = p.accumulatorBits(j, f)
            assert(
              total < (BigInt(1) << w) && total >= (BigInt(1) << (w - 1)),
              s"${f.name}: $total in $w bits"
            )
            assert(p.fieldWidth(j, f) == w)
          }
        }
        p.proofLines.take(2).foreach(l => println(f"[monitor] ${1 / period}%.0f Hz: $l"))
      }
    }

  /** Largest |power - u^p| over the bound, and the largest relative error at u >= 2^-K, over `codes`. */
  private def measure(t: PowerTable, codes: Iterator[BigInt]): (Double, Double) =
    codes.foldLeft((0.0, 0.0)) { case ((worst, rel), a) =>
      val (hw, exact) = (t.powerValue(a), t.exactPower(a))
      val err = math.abs(hw - exact)
      assert(
        err <= t.errorBound(a),
        s"p = ${t.exponent}, code $a: |$hw - $exact| = $err above the bound ${t.errorBound(a)}"
      )
      (worst.max(err / t.errorBound(a)), if (a >= t.floorCode) rel.max(err / exact) else rel)
    }

  it should "bound the power table's error relative to the load and meet the bound on every code " +
    "(exhaustive, 17-bit magnitudes)" in {
      for (p <- Seq(1.0, 1.5, 3.0, 10.0 / 3.0, 10.0); segments <- Seq(5, 6)) {
        val t = PowerTable(p, codeBits = 17, segmentBits = segments, fracBits = 17, rangeBits = 40)
        val (worst, rel) = measure(t, (0 until (1 << 17)).iterator.map(BigInt(_)))
        println(
          f"[monitor] power table p = $p%.4f, ${t.regions} regions x ${t.segmentsPerRegion} " +
            f"segments: max relative error $rel%.3e at u >= 2^-${t.octaves} (derived " +
            f"${t.relativeBound}%.3e), floor ${t.absoluteBound}%.2e; worst error at " +
            f"${worst * 100}%.0f%% of its bound"
        )
        assert(rel <= t.relativeBound && worst > 0.2, s"p = $p: the bound is met but loose (${worst * 100}%)")
        // Inside a segment the mantissa does not decrease (the max power is a segment's last code).
        assert(
          (0 until (1 << 17) - 1).forall(a =>
            t.locate(BigInt(a))._1 != t.locate(BigInt(a + 1))._1 ||
              t.power(BigInt(a)) <= t.power(BigInt(a + 1))
          ),
          s"p = $p: not monotone inside a segment"
        )
      }
      // Fixed target at the defaults: 3e-4 of the load for p = 3 and 10/3 (1e-4 of T_av), whatever the load's
      // share of full scale.
      for (p <- Seq(3.0, 10.0 / 3.0)) {
        val t = PowerTable(p, codeBits = 27, segmentBits = 6, fracBits = 17, rangeBits = 40)
        assert(
          t.relativeBound <= 3e-4 && t.octaves >= 12,
          s"p = $p: relative bound ${t.relativeBound}, ${t.octaves} octaves"
        )
      }
    }

  it should "keep |tau|^p relative for loads far below full scale (27-bit codes: every " +
    "octave sampled, dropped offset bits)" in {
      val rng = new scala.util.Random(reducerload.testutil.Seeds("power-table-wide", 1303L))
      for (p <- Seq(3.0, 10.0 / 3.0, 10.0)) {
        val t = PowerTable(p, codeBits = 27, segmentBits = 6, fracBits = 17, rangeBits = 40)
        assert(t.droppedBits == 3)
        // Log-uniform codes: a random bit length, then random bits below the leading one; and both ends of
        // every segment.
        val random = Iterator.fill(200000) {
          val len = rng.nextInt(28);
          if (len == 0) BigInt(0) else (BigInt(1) << (len - 1)) + BigInt(len - 1, rng.self)
        }
        val ends = (1 until 27).iterator.flatMap(b => Seq(BigInt(1) << b, (BigInt(1) << b) - 1))
        val (worst, rel) = measure(t, random ++ ends)
        // The issue's case: 5 N·m of a 1024 N·m full scale, u^3 = 1.2e-7, below the old table's LSB.
        val a = BigInt(5L << 17)
        val issue = math.abs(t.powerValue(a) / t.exactPower(a) - 1)
        println(
          f"[monitor] 27-bit power table p = $p%.4f: max relative error $rel%.3e (derived " +
            f"${t.relativeBound}%.3e) at u >= 2^-${t.octaves}, worst at " +
            f"${worst * 100}%.0f%% of its bound; u = 5/1024: relative error $issue%.2e; " +
            f"damage sum ${t.shift.max} bits wider"
        )
        assert(issue <= t.relativeBound + t.absoluteBound / t.exactPower(a))
      }
    }

  it should "lay out the register map without gaps and encode and decode every value" in {
    val p = MonitorStimulus.threeJoints
    val m = p.registerMap
    assert(m.entries.head.address == 0 && m.entries.zip(m.entries.tail).forall { case (a, b) =>
      b.address == a.address + a.words
    })
    assert(m.words == m.entries.last.address + m.entries.last.words)
    val snap = MonitorSnapshot(
      7,
      (0 until p.joints).map(j =>
        JointState.cleared(p, j).copy(peakTorque = -5, damageSum = (BigInt(1) << 60) + 3)
      )
    )
    assert(MonitorSnapshot.fromBank(p, snap.bank(p)) == snap)
    assert(m.markdown.size == m.entries.size + 2)
  }

  it should "match the generated text in docs/monitor.md" in {
    val doc = new String(Files.readAllBytes(Paths.get("docs/monitor.md")), "UTF-8")
    assert(
      doc.contains(MonitorDoc.text),
      "docs/monitor.md is out of date: paste the output of ./sbt --error \"runMain " +
        "reducerload.monitor.MonitorDoc\""
    )
  }

  it should "refuse bad parameters, naming the joint and the parameter" in {
    val p = MonitorStimulus.threeJoints
    val cases: Seq[(String, () => MonitorParams, Seq[String])] = Seq(
      (
        "T_M below T_R",
        () => p.copy(momentaryPeakNm = Seq(100.0, 12.0, 7.25)),
        Seq("joint 2 (elbow)", "momentaryPeakNm")
      ),
      (
        "T_R not positive",
        () => p.copy(repeatedPeakNm = Seq(40.0, 12.3, -1.0)),
        Seq("joint 3 (wrist)", "repeatedPeakNm")
      ),
      (
        "T_R NaN",
        () => p.copy(repeatedPeakNm = Seq(Double.NaN, 12.3, 3.5)),
        Seq("joint 1 (base)", "repeatedPeakNm")
      ),
      (
        "T_M beyond the format",
        () => p.copy(momentaryPeakNm = Seq(300.0, 30.7, 7.25)),
        Seq("joint 1 (base)", "momentaryPeakNm", "maximum")
      ),
      (
        "exponent below 1",
        () => p.copy(lifeExponents = Seq(3.0, 0.5, 1.5)),
        Seq("joint 2 (elbow)", "lifeExponents")
      ),
      (
        "exponent above 10",
        () => p.copy(lifeExponents = Seq(3.0, 3.0, 10.5)),
        Seq("joint 3 (wrist)", "lifeExponents")
      ),
      (
        "gear ratio zero",
        () => p.copy(gearRatios = Seq(0.0, 81.0, 50.0)),
        Seq("joint 1 (base)", "gearRatios")
      ),
      ("no bins", () => p.copy(histogramBins = Seq(16, 0, 8)), Seq("joint 2 (elbow)", "histogramBins")),
      (
        "bins beyond the range",
        () => p.copy(histogramBins = Seq(16, 10, 20)),
        Seq("joint 3 (wrist)", "histogramBinWidthNm")
      ),
      (
        "bin narrower than an LSB",
        () => p.copy(histogramBinWidthNm = Seq(1e-9, 5.5, 1.9)),
        Seq("joint 1 (base)", "histogramBinWidthNm")
      ),
      (
        "torque format too narrow for the table",
        () =>
          p.copy(
            torqueFormats = Seq(FixedFormat(8, 16), FixedFormat(3, 2), FixedFormat(4, 13)),
            momentaryPeakNm = Seq(100.0, 7.0, 7.25),
            repeatedPeakNm = Seq(40.0, 3.0, 3.5)
          ),
        Seq("joint 2 (elbow)", "torqueFormats")
      ),
      (
        "a Seq of the wrong length",
        () => p.copy(gearRatios = Seq(1.0, 2.0)),
        Seq("gearRatios has 2 entries for 3 joints")
      ),
      ("duplicate names", () => p.copy(jointNames = Seq("a", "a", "b")), Seq("jointNames", "distinct")),
      ("sample period zero", () => p.copy(samplePeriodS = 0.0), Seq("samplePeriodS")),
      ("target years negative", () => p.copy(targetYears = -1), Seq("targetYears")),
      (
        "test preset beyond the budget",
        () => p.copy(testStartAfterSamples = Some(p.sampleBudget + 1)),
        Seq("testStartAfterSamples")
      )
    )
    cases.foreach { case (what, make, words) =>
      val e = intercept[IllegalArgumentException](make())
      words.foreach(w => assert(e.getMessage.contains(w), s"$what: '${e.getMessage}' does not name '$w'"))
    }
  }
}
