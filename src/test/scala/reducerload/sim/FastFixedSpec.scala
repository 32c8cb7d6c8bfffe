package reducerload.sim

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.fixedpoint.{FixedFormat, Rounding}
import reducerload.load.{LoadDatapathModel, LoadParams}
import reducerload.testutil.Seeds

import scala.util.Random

/** The fast conversions give the reference's codes and doubles exactly, ties and extremes included. */
class FastFixedSpec extends AnyFlatSpec {
  behavior of "FastFixed"

  private val formats = Seq(FixedFormat(3, 20), FixedFormat(5, 20), FixedFormat(10, 24), FixedFormat(62, 26), FixedFormat(2, 40))

  /** Random values at every scale, exact ties (k + 1/2 codes), and their neighbours one ulp away. */
  private def values(f: FixedFormat, rng: Random): Seq[Double] = {
    val random = Seq.fill(20000)((rng.nextDouble() * 2 - 1) * math.pow(10, rng.nextInt(12) - 6))
    val ties = Seq.fill(5000) {
      val tie = math.scalb(rng.nextInt(1 << 24) - (1 << 23) + 0.5, -f.fracBits) * math.pow(2, rng.nextInt(4))
      Seq(tie, math.nextUp(tie), math.nextDown(tie))
    }.flatten
    random ++ ties ++ Seq(0.0, -0.0, 1 + math.scalb(1.0, -f.fracBits - 1), 1e30, -1e30, Double.MinPositiveValue, 4.9e-300)
  }

  it should "quantize and convert like FixedFormat, bit for bit" in {
    val rng = new Random(Seeds("fast-fixed", 61L))
    formats.foreach { f =>
      val xs = values(f, rng)
      val wrong = xs.filter(x => FastFixed.quantizeHalfUp(x, f) != f.quantize(x, Rounding.HalfUp))
      assert(wrong.isEmpty, s"$f: quantize differs at ${wrong.take(5).map(x => f"$x%.20g").mkString(", ")}")
      val saturated = xs.filter(x => FastFixed.codeHalfUp(x, f) != f.fromDouble(x, Rounding.HalfUp)._1)
      assert(saturated.isEmpty, s"$f: fromDouble differs at ${saturated.take(5)}")
      val codes = xs.map(x => f.quantize(x, Rounding.HalfUp)) ++ Seq(f.minRaw, f.maxRaw, BigInt(1) << 60, -(BigInt(1) << 70) + 1)
      val back = codes.filter(c => FastFixed.toDouble(c, f.fracBits) != FixedFormat.scaleDown(c, f.fracBits))
      assert(back.isEmpty, s"$f: toDouble differs at ${back.take(5)}")
    }
  }

  it should "give the models' angle codes, wrapping included" in {
    val rng = new Random(Seeds("fast-fixed-angles", 62L))
    val model = new LoadDatapathModel(LoadParams.default)
    val bits = LoadParams.default.angleBits
    val angles = Seq.fill(20000)((rng.nextDouble() * 2 - 1) * math.pow(10, rng.nextInt(5) - 1)) ++
      Seq.fill(2000)(2 * math.Pi * math.scalb(rng.nextInt(1 << 20) + 0.5, -bits)) ++ Seq(0.0, math.Pi, -math.Pi, 2 * math.Pi, 1e6)
    val wrong = angles.filter(a => FastFixed.angleCode(a, FastFixed.angleFormat(bits)) != model.angleCode(a))
    assert(wrong.isEmpty, s"angle codes differ at ${wrong.take(5)}")
  }
}
