package reducerload.sim.model

import reducerload.testutil.CompiledParams
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.fixedpoint.{FixedFormat, Rounding}
import reducerload.cordic.CordicModel
import reducerload.arm.{ArmModel, ArmParams}
import reducerload.compiler.Compiler
import reducerload.config.LoadParams
import reducerload.graph.SampleCodes
import reducerload.load.LoadChecks
import reducerload.testutil.ArmGolden
import reducerload.testutil.Seeds

import scala.util.Random

/** The fast conversions give the reference's codes and doubles exactly, ties and extremes included. */
class FastFixedSpec extends AnyFlatSpec {
  behavior of "FastFixed"

  private val formats =
    Seq(FixedFormat(3, 20), FixedFormat(5, 20), FixedFormat(10, 24), FixedFormat(62, 26), FixedFormat(2, 40))

  /** Random values at every scale, exact ties (k + 1/2 codes), and their neighbours one ulp away. */
  private def values(f: FixedFormat, rng: Random): Seq[Double] = {
    val random = Seq.fill(20000)((rng.nextDouble() * 2 - 1) * math.pow(10, rng.nextInt(12) - 6))
    val ties = Seq
      .fill(5000) {
        val tie =
          math.scalb(rng.nextInt(1 << 24) - (1 << 23) + 0.5, -f.fracBits) * math.pow(2, rng.nextInt(4))
        Seq(tie, math.nextUp(tie), math.nextDown(tie))
      }
      .flatten
    random ++ ties ++ Seq(
      0.0,
      -0.0,
      1 + math.scalb(1.0, -f.fracBits - 1),
      1e30,
      -1e30,
      Double.MinPositiveValue,
      4.9e-300
    )
  }

  it should "quantize and convert like FixedFormat, bit for bit" in {
    val rng = new Random(Seeds("fast-fixed", 61L))
    formats.foreach { f =>
      val xs = values(f, rng)
      val wrong = xs.filter(x => FastFixed.quantizeHalfUp(x, f) != f.quantize(x, Rounding.HalfUp))
      assert(wrong.isEmpty, s"$f: quantize differs at ${wrong.take(5).map(x => f"$x%.20g").mkString(", ")}")
      val saturated = xs.filter(x => FastFixed.codeHalfUp(x, f) != f.fromDouble(x, Rounding.HalfUp)._1)
      assert(saturated.isEmpty, s"$f: fromDouble differs at ${saturated.take(5)}")
      val codes = xs.map(x => f.quantize(x, Rounding.HalfUp)) ++ Seq(
        f.minRaw,
        f.maxRaw,
        BigInt(1) << 60,
        -(BigInt(1) << 70) + 1
      )
      val back = codes.filter(c => FastFixed.toDouble(c, f.fracBits) != FixedFormat.scaleDown(c, f.fracBits))
      assert(back.isEmpty, s"$f: toDouble differs at ${back.take(5)}")
    }
  }

  it should "give the models' angle codes, wrapping included" in {
    val rng = new Random(Seeds("fast-fixed-angles", 62L))
    val model = new ArmModel(LoadParams.default.arm)
    val bits = LoadParams.default.arm.numerics.angleBits
    val angles = Seq.fill(20000)((rng.nextDouble() * 2 - 1) * math.pow(10, rng.nextInt(5) - 1)) ++
      Seq.fill(2000)(2 * math.Pi * math.scalb(rng.nextInt(1 << 20) + 0.5, -bits)) ++ Seq(
        0.0,
        math.Pi,
        -math.Pi,
        2 * math.Pi,
        1e6
      )
    val wrong = angles.filter(a => FastFixed.angleCode(a, FastFixed.angleFormat(bits)) != model.angleCode(a))
    assert(wrong.isEmpty, s"angle codes differ at ${wrong.take(5)}")
  }

  it should "multiply and round like FixedFormat.shiftRound on the exact product, or refuse" in {
    val rng = new Random(Seeds("fast-fixed-multiply", 63L))
    def long(bits: Int) = rng.nextLong() >> (64 - bits)
    val cases = Seq.fill(50000)((long(1 + rng.nextInt(63)), long(1 + rng.nextInt(63)), rng.nextInt(127))) ++
      Seq(
        (Long.MinValue, Long.MinValue, 126),
        (Long.MaxValue, Long.MinValue, 63),
        (-1L, 1L, 1),
        (3L, 1L, 1),
        (-3L, 1L, 1),
        (5L, -7L, 0)
      )
    for ((a, b, drop) <- cases; rounding <- Seq(Rounding.HalfUp, Rounding.Truncate)) {
      val exact = FixedFormat.shiftRound(BigInt(a) * BigInt(b), drop, rounding)
      if (exact.isValidLong)
        assert(FastFixed.mulShiftRound(a, b, drop, rounding) == exact.toLong, s"$a * $b >> $drop ($rounding)")
      else assertThrows[ArithmeticException](FastFixed.mulShiftRound(a, b, drop, rounding))
    }
  }

  it should "compute CORDIC sin/cos codes like CordicModel for every preset (exhaustive below 17 angle bits)" in {
    val rng = new Random(Seeds("fast-cordic", 64L))
    LoadParams.allPresets.values.map(_.cordic).toSeq.distinct.foreach { c =>
      val model = new CordicModel(c)
      val fast = new FastCordic(c)
      val angles =
        if (c.angleBits <= 16) (0L until (1L << c.angleBits))
        else Seq.fill(30000)(rng.nextLong() & ((1L << c.angleBits) - 1))
      val out = new Array[Long](2)
      val wrong = angles.filter { a =>
        fast.sinCosRaw(a, out, 0)
        val (cos, sin) = model.sinCosRaw(BigInt(a))
        out(0) != cos || out(1) != sin
      }
      assert(wrong.isEmpty, s"${c.tag}: sin/cos differ at angle codes ${wrong.take(5)}")
    }
  }

  /**
   * `p`'s long model against its BigInt model on `samples` plus random extreme port codes (clamped and
   * flagged).
   */
  private def checkFastModel(label: String, p: ArmParams, samples: Seq[SampleCodes], rng: Random): Unit = {
    assert(FastArmModel.supports(p), s"$label: the long model does not cover it")
    val model = new ArmModel(p)
    val fast = new FastArmModel(p)
    val n = p.numerics
    val extremes = Seq.fill(200) {
      val e = samples(rng.nextInt(samples.size))
      def extreme(f: FixedFormat) = if (rng.nextBoolean()) f.maxRaw else f.minRaw
      SampleCodes(
        e.angles,
        e.velocities.map(_ => extreme(n.velocityPortFormat)),
        e.accelerations.map(_ => extreme(n.accelerationPortFormat))
      )
    }
    val all = samples ++ extremes
    val wrong = all.filter(s => fast.evaluate(s) != model.evaluate(s))
    assert(wrong.isEmpty, s"$label: differs at ${wrong.take(3)}")
    assert(
      all.exists(s => model.evaluate(s).outOfRange.exists(identity)) && all.exists(s =>
        !model.evaluate(s).outOfRange.exists(identity)
      )
    )
  }

  it should "evaluate the joint-3 datapath like its BigInt model, out-of-range inputs included, for every preset" in {
    val rng = new Random(Seeds("fast-load-model", 65L))
    LoadParams.presets.foreach { case (name, p) =>
      val model = new LoadChecks.Joint3Model(p)
      val samples = Seq.fill(4000)(LoadChecks.randomSample(p.robot, rng)).map(model.encode) ++
        Seq.fill(1000)(LoadChecks.outOfRangeSample(p.robot, rng)).map(model.encode)
      checkFastModel(s"preset $name", p.arm, samples, rng)
    }
  }

  it should "evaluate every joint of the UR5 and the Panda like their BigInt models" in {
    val rng = new Random(Seeds("fast-arm-model", 66L))
    Seq("ur5", "panda").foreach { robot =>
      val traces = ArmGolden.of(robot)
      val p = Compiler.arm(traces.head.config)
      val model = new ArmModel(p)
      checkFastModel(robot, p, traces.flatMap(_.samples).take(1500).map(model.encode), rng)
    }
  }
}
