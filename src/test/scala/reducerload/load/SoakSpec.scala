package reducerload.load

import reducerload.testutil.CompiledParams
import reducerload.config.LoadParams
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.app.Soak
import reducerload.sim.rtl.{Cycle, Stream, StreamChecker}
import reducerload.testutil.{Seeds, SimBackend}

import scala.util.Random

/** The short form of `./sbt "run soak"` (which streams 10^6 samples), and the checker it relies on. */
class SoakSpec extends AnyFlatSpec {
  behavior of "the soak"

  it should "stream 20,000 samples with bubbles, resets and out-of-range inputs, every output bit-exact" in {
    assume(SimBackend.isVerilator, "the soak runs on Verilator")
    val seed = Seeds("soak-short", 51L)
    val r = Soak.run(LoadParams.default.arm, 20000, seed, resets = 4)
    println(
      f"[soak] ${r.checked} outputs checked over ${r.cycles} cycles, ${r.mismatches} mismatches, ${r.samples / r.seconds}%.0f samples/s"
    )
    assert(r.mismatches == 0, r.examples.mkString("\n"))
    assert(r.checked > 19000)
  }

  it should "catch a dropped, a duplicated and a late output (the checker can fail)" in {
    val rng = new Random(Seeds("checker", 52L))
    val stim =
      Stream.randomStimulus(rng, (0 until 200).map(BigInt(_)), bubble = 0.2, resets = 2) ++ IndexedSeq.fill(
        6
      )(Cycle.Bubble)
    val good = Stream.expected(stim, 5)
    def mismatches(observed: IndexedSeq[Option[BigInt]]) = {
      val c = new StreamChecker[BigInt, BigInt](5, identity)
      stim.indices.foreach { t => c.observe(t, observed(t)); c.drive(t, stim(t)) }
      c.mismatches
    }
    assert(mismatches(good) == 0)
    val firstValid = good.indexWhere(_.isDefined)
    assert(mismatches(good.updated(firstValid, None)) > 0, "a dropped output went unnoticed")
    val firstBubble = good.indexWhere(_.isEmpty, firstValid)
    assert(
      mismatches(good.updated(firstBubble, good(firstBubble - 1))) > 0,
      "a duplicated output went unnoticed"
    )
    assert(mismatches(None +: good.init) > 0, "a late stream went unnoticed")
  }
}
