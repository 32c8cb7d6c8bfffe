package reducerload.cordic

import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.testutil.{Seeds, SimBackend}

import scala.util.Random
import reducerload.testutil.SimBackend.multiplierImpl // the JVM simulator builds the multipliers' Chisel twin

class CordicSinCosSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "CordicSinCos"

  /** One simulation per design: stream the angles with bubbles and resets, check bits, timing and error. */
  private def streamAndCheck(
      label: String,
      p: CordicParams,
      angles: Random => IndexedSeq[BigInt],
      seed: Long,
      resets: Int
  ): Unit = {
    val rng = new Random(Seeds(label, seed))
    val stim = CordicChecks.stimulus(p, angles(rng), rng, resets)
    test(new CordicSinCos(p)).withAnnotations(SimBackend.annotations) { dut =>
      val verdict = CordicChecks.check(p, stim, CordicDriver.run(dut, stim))
      println(
        f"[cordic] $label ${p.tag}: ${verdict.checked} outputs equal to the model, max |error| " +
          f"${verdict.maxError}%.3e <= bound ${p.errorBound}%.3e, latency ${p.latency}"
      )
      assert(
        verdict.mismatches.isEmpty,
        verdict.mismatches.mkString("RTL differs from the model:\n", "\n", "")
      )
      assert(verdict.checked > 0)
      assert(
        verdict.maxError <= p.errorBound,
        s"max error ${verdict.maxError} exceeds the derived bound ${p.errorBound}"
      )
    }
  }

  it should "equal the model on every angle code of a small unit, streamed with bubbles and resets" in {
    val p = CordicParams.small
    val all = (0 until (1 << p.angleBits)).map(BigInt(_))
    streamAndCheck(
      "small-exhaustive",
      p,
      rng => rng.shuffle(all) ++ CordicChecks.quadrantCrossers(p),
      1L,
      resets = 3
    )
  }

  it should "equal the model with three iterations per register stage" in {
    val p = CordicParams.small.copy(iterationsPerStage = 3)
    assert(p.latency == 1 + 3 + 1)
    val all = (0 until (1 << p.angleBits)).map(BigInt(_))
    streamAndCheck("small-3-per-stage", p, rng => rng.shuffle(all), 2L, resets = 2)
  }

  it should "equal the model and meet its bound on every angle code of the paper preset" in {
    val p = CordicParams.paper
    val all = (0 until (1 << p.angleBits)).map(BigInt(_))
    streamAndCheck(
      "paper-exhaustive",
      p,
      rng => {
        val codes = rng.shuffle(all)
        CordicChecks.quadrantCrossers(p) ++ codes.take(SimBackend.scale(codes.size))
      },
      3L,
      resets = 4
    )
  }

  it should "equal the model and meet its bound on seeded random angles of the precise preset" in {
    val p = CordicParams.precise
    streamAndCheck(
      "precise-random",
      p,
      rng => CordicChecks.quadrantCrossers(p) ++ CordicChecks.randomAngles(p, rng, SimBackend.scale(20000)),
      4L,
      resets = 4
    )
  }

  it should "equal the model on every angle code of a small residual-rotation unit" in {
    val p = CordicParams.smallResidual
    streamAndCheck(
      "small-residual-exhaustive",
      p,
      rng => rng.shuffle((0 until (1 << p.angleBits)).map(BigInt(_))),
      5L,
      resets = 3
    )
  }

  it should "equal the model and meet its bound on seeded random angles of the residual preset" in {
    val p = CordicParams.residual
    streamAndCheck(
      "residual-random",
      p,
      rng => CordicChecks.quadrantCrossers(p) ++ CordicChecks.randomAngles(p, rng, SimBackend.scale(20000)),
      6L,
      resets = 3
    )
  }

  it should "equal the model on every angle code of a small start-table unit" in {
    val p = CordicParams.smallTable
    streamAndCheck(
      "small-table-exhaustive",
      p,
      rng => rng.shuffle((0 until (1 << p.angleBits)).map(BigInt(_))),
      8L,
      resets = 3
    )
  }

  it should "equal the model one clock later with the table's route register (registered routes)" in {
    val p = CordicParams.smallTable.copy(tableRouteRegister = true)
    assert(p.latency == CordicParams.smallTable.latency + 1 && p.tag != CordicParams.smallTable.tag)
    streamAndCheck(
      "small-table-route-register",
      p,
      rng => rng.shuffle((0 until (1 << p.angleBits)).map(BigInt(_))),
      10L,
      resets = 3
    )
  }

  it should "equal the model and meet its bound on seeded random angles of the table-residual preset" in {
    val p = CordicParams.tableResidual
    streamAndCheck(
      "table-residual-random",
      p,
      rng => CordicChecks.quadrantCrossers(p) ++ CordicChecks.randomAngles(p, rng, SimBackend.scale(20000)),
      9L,
      resets = 3
    )
  }
}
