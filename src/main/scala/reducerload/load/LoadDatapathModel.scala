package reducerload.load

import reducerload.cordic.CordicModel
import reducerload.fixedpoint.{FixedFormat, Rounding}

/** Raw input codes of one sample, as the hardware sees them. */
final case class LoadInputCodes(t1: BigInt, t2: BigInt, t3: BigInt, d: Seq[BigInt], dd: Seq[BigInt])

/** Raw output: load code and out-of-range flag. */
final case class LoadOutputCodes(load: BigInt, outOfRange: Boolean)

/** Bit-accurate model of [[LoadDatapath]], plus the conversions between SI values and codes. */
final class LoadDatapathModel(val p: LoadParams) {
  private val cordic = new CordicModel(p.cordic)
  private val turn = BigInt(1) << p.angleBits

  private def clamp(x: BigInt, limit: BigInt): (BigInt, Boolean) = FixedFormat.clamp(x, -limit, limit)

  def evaluate(in: LoadInputCodes): LoadOutputCodes = {
    val (d, dFlags) = in.d.zip(p.velocityLimitRaw).map { case (x, l) => clamp(x, l) }.unzip
    val (dd, ddFlags) = in.dd.zip(p.accelerationLimitRaw).map { case (x, l) => clamp(x, l) }.unzip
    val t23 = (in.t2 + in.t3).mod(turn)
    val t123 = (t23 + in.t1).mod(turn)
    val (c3, s3) = cordic.sinCosRaw(in.t3)
    val (c23, s23) = cordic.sinCosRaw(t23)
    val (_, s123) = cordic.sinCosRaw(t123)
    val total = LoadRecipe(p, IntArith, RecipeInputs(d(0), d(1), dd(0), dd(1), dd(2), c23, c3, s23, s3, s123))
    val rounded = FixedFormat.shiftRound(total, p.internalFracBits - p.outputFracBits, Rounding.HalfUp)
    val (load, saturated) = FixedFormat.saturate(rounded, p.outputFormat)
    LoadOutputCodes(load, (dFlags ++ ddFlags).exists(identity) || saturated)
  }

  // ---- SI <-> codes (round to nearest, as the error bound assumes) ----

  /** Binary angle code of an angle in radians, any real value (wraps modulo one turn). */
  def angleCode(rad: Double): BigInt = {
    require(!rad.isNaN && !rad.isInfinite, s"angle $rad is not a finite number")
    val turns = rad / (2 * math.Pi)
    FixedFormat(62, p.angleBits).quantize(turns - math.floor(turns), Rounding.HalfUp).mod(turn)
  }

  /** Codes of a sample; values beyond the format (not only the declared range) saturate at the format. */
  def encode(s: JointSample): LoadInputCodes = {
    def code(x: Double, f: FixedFormat) = f.fromDouble(x, Rounding.HalfUp)._1
    LoadInputCodes(
      angleCode(s.t1),
      angleCode(s.t2),
      angleCode(s.t3),
      Seq(s.d1, s.d2, s.d3).zip(p.velocityFormats).map { case (x, f) => code(x, f) },
      Seq(s.dd1, s.dd2, s.dd3).zip(p.accelerationFormats).map { case (x, f) => code(x, f) }
    )
  }

  def loadOf(out: LoadOutputCodes): Double = p.outputFormat.toDouble(out.load)

  /** Load in N·m for a sample in SI units. */
  def evaluate(s: JointSample): Double = loadOf(evaluate(encode(s)))
}
