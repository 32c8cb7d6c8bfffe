package reducerload.load

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.sim.{Cycle, LoadDriver, Stream}
import reducerload.testutil.{Golden, GoldenTrace, Seeds, SimBackend}

import scala.collection.mutable.ArrayBuffer
import scala.util.Random

/**
 * One simulation per design: every golden trace back to back (one sample per clock), then seeded
 * random samples (some beyond the declared ranges) with bubbles and resets. Checked: bit-exact
 * against the model at exactly `latency` cycles, an output every clock over the golden part, and
 * the error against the independent golden loads within the derived bound and the target.
 */
class LoadDatapathSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "LoadDatapath"

  private def runDesign(label: String, p: LoadParams, target: Double, reference: GoldenTrace => IndexedSeq[Double], seed: Long): Unit = {
    val traces = Golden.all
    traces.foreach(t => assert(t.robot == p.robot, s"golden trace ${t.name} is for another robot: ${t.robot}"))
    assert(p.errorBound <= target, s"$label: derived bound ${p.errorBound} misses the target $target")
    val model = new LoadDatapathModel(p)
    val rng = new Random(Seeds(label, seed))
    val golden = traces.flatMap(_.samples.map(model.encode)).toIndexedSeq
    val random = IndexedSeq.fill(SimBackend.scale(4000)) {
      model.encode(if (rng.nextInt(8) == 0) LoadChecks.outOfRangeSample(p.robot, rng) else LoadChecks.randomSample(p.robot, rng))
    }
    val latency = LoadDatapath.latency(p)
    val period = p.samplePeriod
    val stim = Stream.spaced((golden.map(Cycle.Sample(_)) ++ Stream.randomStimulus(rng, random, bubble = 0.2, resets = 3)).iterator, period)
      .toIndexedSeq ++ IndexedSeq.fill(latency + 1)(Cycle.Bubble)

    test(new LoadDatapath(p)).withAnnotations(SimBackend.annotations) { dut =>
      val observed = ArrayBuffer.empty[Option[LoadOutputCodes]]
      LoadDriver.run(dut, stim.iterator, (_, out) => observed += out)

      val verdict = LoadChecks.checkAgainstModel(p, stim, observed.toIndexedSeq)
      assert(verdict.mismatches.isEmpty, verdict.mismatches.mkString(s"$label: RTL differs from the model:\n", "\n", ""))

      // Throughput: the golden part comes out one load per sample period, in order, with nothing missing.
      val goldenOut = golden.indices.map(k => observed(latency + k * period))
      assert(goldenOut.forall(_.isDefined), s"$label: a golden sample produced no output (valid low)")
      val loads = goldenOut.map(o => model.loadOf(o.get))
      assert(goldenOut.forall(!_.get.outOfRange), s"$label: an in-range golden sample raised outOfRange")

      val offsets = traces.scanLeft(0)(_ + _.samples.size)
      traces.zip(offsets).foreach { case (t, from) =>
        val hw = loads.slice(from, from + t.samples.size)
        val ref = reference(t)
        val err = hw.zip(ref).map { case (h, r) => math.abs(h - r) }.max
        val errRnea = if (p.model == LoadModel.Exact) hw.zip(t.rnea).map { case (h, r) => math.abs(h - r) }.max else Double.NaN
        println(f"[load] $label ${t.name}%-13s ${t.samples.size}%5d samples: max |hw - ${p.model.name}| $err%.3e N·m" +
          (if (p.model == LoadModel.Exact) f", max |hw - rnea| $errRnea%.3e" else "") + f" (bound ${p.errorBound}%.3e, target $target%.0e)")
        assert(err <= p.errorBound, s"$label ${t.name}: error $err exceeds the derived bound ${p.errorBound}")
        if (p.model == LoadModel.Exact) assert(errRnea <= p.errorBound + 1e-9, s"$label ${t.name}: error vs RNEA $errRnea")
      }
      println(s"[load] $label: ${verdict.checked} outputs bit-exact with the model at latency $latency, " +
        s"${random.size} random samples with bubbles, resets and out-of-range inputs")
    }
  }

  it should "compute the exact load within 1e-4 N·m on every golden trace (default preset)" in {
    runDesign("default", LoadParams.default, 1e-4, _.exact, 21L)
  }

  it should "reproduce the paper's equation (6) within 1e-3 N·m on every golden trace (paper preset)" in {
    runDesign("paper", LoadParams.paper, 1e-3, _.paper, 22L)
  }

  it should "compute the exact load within 1e-3 N·m with one CORDIC unit shared by the three angles (compact preset)" in {
    runDesign("compact", LoadParams.compact, 1e-3, _.exact, 23L)
  }

  it should "take a sample only when ready with a shared CORDIC unit: offered every clock, every third is taken" in {
    val p = LoadParams.smallest
    assert(p.samplePeriod == 3)
    val model = new LoadDatapathModel(p)
    val rng = new Random(Seeds("shared-ready", 24L))
    val offered = IndexedSeq.fill(30)(model.encode(LoadChecks.randomSample(p.robot, rng)))
    val latency = LoadDatapath.latency(p)
    test(new LoadDatapath(p)).withAnnotations(SimBackend.annotations) { dut =>
      // Reset first, then offer a new sample on every clock; what the datapath took becomes the stimulus.
      dut.reset.poke(true.B)
      dut.clock.step()
      dut.reset.poke(false.B)
      val taken = ArrayBuffer.empty[Cycle[LoadInputCodes]]
      val observed = ArrayBuffer.empty[Option[LoadOutputCodes]]
      (offered.map(Some(_)) ++ IndexedSeq.fill(latency + 3)(None)).foreach { s =>
        s match {
          case Some(sample) => LoadDriver.pokeSample(dut, sample)
          case None         => dut.io.in.valid.poke(false.B)
        }
        val ready = dut.io.in.ready.peek().litToBoolean
        taken += (s match { case Some(sample) if ready => Cycle.Sample(sample); case _ => Cycle.Bubble })
        observed += LoadDriver.peekOutput(dut)
        dut.clock.step()
      }
      val takenAt = taken.zipWithIndex.collect { case (Cycle.Sample(_), t) => t }
      assert(takenAt == offered.indices.filter(_ % 3 == 0), s"samples taken at cycles $takenAt, expected every third")
      val verdict = LoadChecks.checkAgainstModel(p, taken.toIndexedSeq, observed.toIndexedSeq)
      assert(verdict.mismatches.isEmpty, verdict.mismatches.mkString("shared unit differs from the model:\n", "\n", ""))
      assert(verdict.checked == offered.size / 3)
      println(s"[load] shared-ready: ${takenAt.size} of ${offered.size} offered samples taken (every third), all bit-exact")
    }
  }
}
