package reducerload.monitor

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.fixedpoint.FixedFormat

import java.nio.file.{Files, Paths}

/** Elaboration-time derivations: the 20-year proof, the power table's bound, the register map, refusals. */
class MonitorParamsSpec extends AnyFlatSpec {
  behavior of "MonitorParams"

  it should "prove every accumulator holds 20 years at 1 kHz and at 16 kHz (6 joints), with no spare top bit" in {
    for (period <- Seq(1e-3, 1.0 / 16000)) {
      val p = MonitorParams.example(period)
      val expectedBudget = BigInt(math.ceil(20 * 365.25 * 86400 / period).toLong)
      assert((p.sampleBudget - expectedBudget).abs <= 1, s"budget ${p.sampleBudget} vs $expectedBudget")
      (0 until p.joints).foreach { j =>
        p.provenAccumulators.foreach { f =>
          val total = p.maxIncrement(j, f) * p.sampleBudget
          val w = p.accumulatorBits(j, f)
          assert(total < (BigInt(1) << w) && total >= (BigInt(1) << (w - 1)), s"${f.name}: $total in $w bits")
          assert(p.fieldWidth(j, f) == w)
        }
      }
      p.proofLines.take(2).foreach(l => println(f"[monitor] ${1 / period}%.0f Hz: $l"))
    }
  }

  it should "bound the power table's error and meet the bound on every code (exhaustive, 17-bit magnitudes)" in {
    for (p <- Seq(1.0, 1.5, 3.0, 10.0 / 3.0, 10.0); segments <- Seq(6, 8)) {
      val t = PowerTable(p, codeBits = 17, segmentBits = segments, fracBits = 17)
      val lsb = math.pow(2.0, -t.fracBits)
      val measured = (0 until (1 << 17)).map(a => math.abs(t.power(BigInt(a)).toDouble * lsb - t.exactPower(BigInt(a)))).max
      println(f"[monitor] power table p = $p%.4f, ${t.segments} segments: max error $measured%.3e, derived bound ${t.errorBound}%.3e (${t.errorBound / lsb}%.2f LSB)")
      assert(measured <= t.errorBound, s"p = $p: measured $measured above the bound ${t.errorBound}")
      assert((0 until (1 << 17) - 1).forall(a => t.power(BigInt(a)) <= t.power(BigInt(a + 1))), s"p = $p: not monotone")
    }
    // Wider codes drop offset bits below the 17 that reach the multiplier; the bound covers it (sampled).
    val wide = PowerTable(10.0 / 3.0, codeBits = 27, segmentBits = 8, fracBits = 17)
    assert(wide.droppedBits == 2)
    val rng = new scala.util.Random(reducerload.testutil.Seeds("power-table-wide", 1303L))
    val worst = Seq.fill(200000)(BigInt(27, rng.self)).map(a => math.abs(wide.power(a).toDouble / (1 << 17) - wide.exactPower(a))).max
    assert(worst <= wide.errorBound, s"27-bit codes: $worst above ${wide.errorBound}")
  }

  it should "lay out the register map without gaps and encode and decode every value" in {
    val p = MonitorStimulus.threeJoints
    val m = p.registerMap
    assert(m.entries.head.address == 0 && m.entries.zip(m.entries.tail).forall { case (a, b) => b.address == a.address + a.words })
    assert(m.words == m.entries.last.address + m.entries.last.words)
    val snap = MonitorSnapshot(7, (0 until p.joints).map(j => JointState.cleared(p, j).copy(peakTorque = -5, damageSum = (BigInt(1) << 60) + 3)))
    assert(MonitorSnapshot.fromBank(p, snap.bank(p)) == snap)
    assert(m.markdown.size == m.entries.size + 2)
  }

  it should "match the generated text in docs/monitor.md" in {
    val doc = new String(Files.readAllBytes(Paths.get("docs/monitor.md")), "UTF-8")
    assert(doc.contains(MonitorDoc.text), "docs/monitor.md is out of date: paste the output of ./sbt --error \"runMain reducerload.monitor.MonitorDoc\"")
  }

  it should "refuse bad parameters, naming the joint and the parameter" in {
    val p = MonitorStimulus.threeJoints
    val cases: Seq[(String, () => MonitorParams, Seq[String])] = Seq(
      ("T_M below T_R", () => p.copy(momentaryPeakNm = Seq(100.0, 12.0, 7.25)), Seq("joint 2 (elbow)", "momentaryPeakNm")),
      ("T_R not positive", () => p.copy(repeatedPeakNm = Seq(40.0, 12.3, -1.0)), Seq("joint 3 (wrist)", "repeatedPeakNm")),
      ("T_R NaN", () => p.copy(repeatedPeakNm = Seq(Double.NaN, 12.3, 3.5)), Seq("joint 1 (base)", "repeatedPeakNm")),
      ("T_M beyond the format", () => p.copy(momentaryPeakNm = Seq(300.0, 30.7, 7.25)), Seq("joint 1 (base)", "momentaryPeakNm", "maximum")),
      ("exponent below 1", () => p.copy(lifeExponents = Seq(3.0, 0.5, 1.5)), Seq("joint 2 (elbow)", "lifeExponents")),
      ("exponent above 10", () => p.copy(lifeExponents = Seq(3.0, 3.0, 10.5)), Seq("joint 3 (wrist)", "lifeExponents")),
      ("gear ratio zero", () => p.copy(gearRatios = Seq(0.0, 81.0, 50.0)), Seq("joint 1 (base)", "gearRatios")),
      ("no bins", () => p.copy(histogramBins = Seq(16, 0, 8)), Seq("joint 2 (elbow)", "histogramBins")),
      ("bins beyond the range", () => p.copy(histogramBins = Seq(16, 10, 20)), Seq("joint 3 (wrist)", "histogramBinWidthNm")),
      ("bin narrower than an LSB", () => p.copy(histogramBinWidthNm = Seq(1e-9, 5.5, 1.9)), Seq("joint 1 (base)", "histogramBinWidthNm")),
      ("torque format too narrow for the table", () => p.copy(torqueFormats = Seq(FixedFormat(8, 16), FixedFormat(3, 2), FixedFormat(4, 13)),
        momentaryPeakNm = Seq(100.0, 7.0, 7.25), repeatedPeakNm = Seq(40.0, 3.0, 3.5)), Seq("joint 2 (elbow)", "torqueFormats")),
      ("a Seq of the wrong length", () => p.copy(gearRatios = Seq(1.0, 2.0)), Seq("gearRatios has 2 entries for 3 joints")),
      ("duplicate names", () => p.copy(jointNames = Seq("a", "a", "b")), Seq("jointNames", "distinct")),
      ("sample period zero", () => p.copy(samplePeriodS = 0.0), Seq("samplePeriodS")),
      ("target years negative", () => p.copy(targetYears = -1), Seq("targetYears")),
      ("test preset beyond the budget", () => p.copy(testStartAfterSamples = Some(p.sampleBudget + 1)), Seq("testStartAfterSamples"))
    )
    cases.foreach { case (what, make, words) =>
      val e = intercept[IllegalArgumentException](make())
      words.foreach(w => assert(e.getMessage.contains(w), s"$what: '${e.getMessage}' does not name '$w'"))
    }
  }
}
