package reducerload.cordic

import reducerload.testutil.CompiledParams
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.testutil.Seeds

import scala.util.Random

/** The bit-accurate model against double precision: dense sweeps, no simulator needed. */
class CordicModelSpec extends AnyFlatSpec {
  behavior of "CordicModel"

  private def sweep(label: String, p: CordicParams, codes: Iterable[BigInt]): Unit = {
    val model = new CordicModel(p)
    val err = CordicChecks.maxError(p, codes.map(c => c -> model.sinCosRaw(c)))
    println(
      f"[cordic-model] $label ${p.tag}: ${codes.size} codes, max |error| $err%.3e, bound " +
        f"${p.errorBound}%.3e (${p.errorBound / err}%.1fx margin)"
    )
    assert(err <= p.errorBound, s"$label: max error $err exceeds the derived bound ${p.errorBound}")
  }

  /** 2^18 evenly spaced codes, each with random low bits, plus the quadrant crossers. */
  private def dense(p: CordicParams, label: String, seed: Long): IndexedSeq[BigInt] = {
    val rng = new Random(Seeds(label, seed))
    val step = BigInt(1) << (p.angleBits - 18)
    (0 until (1 << 18)).map(i => BigInt(i) * step + BigInt(p.angleBits - 18, rng.self)) ++ CordicChecks
      .quadrantCrossers(p)
  }

  it should "stay within the derived bound on every code of the paper and small presets" in {
    Seq(CordicParams.small, CordicParams.paper).foreach { p =>
      sweep("exhaustive", p, (0 until (1 << p.angleBits)).map(BigInt(_)))
    }
  }

  it should "stay within the derived bound on a dense sweep of the precise preset" in {
    val p = CordicParams.precise
    sweep("dense", p, dense(p, "precise-dense", 11L))
  }

  it should "stay within the derived bound with the residual rotation (exhaustive small, dense precise)" in {
    val small = CordicParams.smallResidual
    sweep("exhaustive", small, (0 until (1 << small.angleBits)).map(BigInt(_)))
    val p = CordicParams.residual
    sweep("dense", p, dense(p, "residual-dense", 12L))
    assert(
      p.errorBound <= CordicParams.precise.errorBound * 1.5,
      s"residual bound ${p.errorBound} vs precise ${CordicParams.precise.errorBound}"
    )
  }

  it should "stay within the derived bound with a start table (exhaustive small, dense precise)" in {
    val small = CordicParams.smallTable
    sweep("exhaustive", small, (0 until (1 << small.angleBits)).map(BigInt(_)))
    val p = CordicParams.tableResidual
    sweep("dense", p, dense(p, "table-dense", 13L))
    assert(p.errorBound <= CordicParams.precise.errorBound, s"table-residual bound ${p.errorBound}")
  }

  it should "stay within the derived bound when the table feeds the residual " +
    "rotation directly (no shift-add stage)" in {
      val small = CordicParams.smallResidual.copy(tableBits = CordicParams.smallResidual.iterations - 1)
      assert(small.stageIterations.isEmpty)
      sweep("exhaustive", small, (0 until (1 << small.angleBits)).map(BigInt(_)))
      val p = reducerload.config.LoadParams.paper.cordic
      assert(p.stageIterations.isEmpty, "the paper load preset's unit has no shift-add stage")
      sweep("dense", p, dense(p, "table-only-dense", 14L))
    }

  it should "refuse a residual unit whose products would not fit 18x18 multipliers" in {
    val e = intercept[IllegalArgumentException](
      CordicParams(iterations = 6, architecture = CordicArchitecture.ResidualRotation)
    )
    assert(e.getMessage.contains("iterations"))
  }

  it should "be exact at the quadrant boundaries: cos 0 = 1, sin 90 deg = 1, and so on within the bound" in {
    val p = CordicParams.precise
    val model = new CordicModel(p)
    val quarter = BigInt(1) << (p.angleBits - 2)
    val expect = Seq((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))
    expect.zipWithIndex.foreach { case ((c, s), q) =>
      val (mc, ms) = model.sinCos(quarter * q)
      assert(
        math.abs(mc - c) <= p.errorBound && math.abs(ms - s) <= p.errorBound,
        s"quadrant $q: got ($mc, $ms)"
      )
    }
  }

  it should "reject invalid parameters at elaboration, naming the parameter" in {
    def refused(p: => CordicParams, word: String): Unit = {
      val e = intercept[IllegalArgumentException](p)
      assert(e.getMessage.contains(word), s"message '${e.getMessage}' does not name $word")
    }
    refused(CordicParams(iterations = 0), "iterations")
    refused(CordicParams(iterations = 1), "iterations")
    refused(CordicParams(outputBits = 12, guardBits = 0, iterations = 20), "iterations")
    refused(CordicParams(angleBits = 12, angleGuardBits = 0, iterations = 14), "iterations")
    refused(CordicParams(angleBits = 4), "angleBits")
    refused(CordicParams(outputBits = 3), "outputBits")
    refused(CordicParams(guardBits = -1), "guardBits")
    refused(CordicParams(angleGuardBits = 40), "angleGuardBits")
    refused(CordicParams(iterationsPerStage = 0), "iterationsPerStage")
    refused(CordicParams(tableBits = 13), "tableBits")
    refused(CordicParams(iterations = 8, tableBits = 7), "iterations")
  }
}
