package reducerload.load

import reducerload.fixedpoint.{FixedFormat, Rounding}

/**
 * The arithmetic the datapath is made of. [[LoadRecipe]] is written once against this interface and
 * run twice: on hardware ([[TimedArith]]) and on integers ([[IntArith]], the bit-accurate model), so
 * the two cannot drift apart in structure; the model is checked against double precision and the
 * independent golden traces, the hardware against the model bit for bit.
 */
trait LoadArith[T] {

  /** `a + (b << bShift)`; operands share their fraction bits; the result fits `out` (proven range). */
  def add(a: T, aFmt: FixedFormat, b: T, bFmt: FixedFormat, bShift: Int, out: FixedFormat): T

  /** `a * b` dropped to `out.fracBits` with `rounding`; the result fits `out` (proven range). */
  def mul(a: T, aFmt: FixedFormat, b: T, bFmt: FixedFormat, out: FixedFormat, rounding: Rounding): T

  /** A folded elaboration-time constant. */
  def constant(raw: BigInt, fmt: FixedFormat): T
}

/** The per-sample inputs of the recipe: clamped velocities and accelerations, and the five sin/cos values. */
final case class RecipeInputs[T](d1: T, d2: T, dd1: T, dd2: T, dd3: T, c23: T, c3: T, s23: T, s3: T, s123: T)

object LoadRecipe {

  /**
   * tau3 at `p.internalFracBits`, as in SPEC.md (dd2 weight 1) or the paper's equation (6) (weight 2):
   * A dd1 c23 + B (dd1 + k dd2) c3 + A d1^2 s23 + B (d1+d2)^2 s3 + C (dd1+dd2+dd3) + D s123.
   */
  def apply[T](p: LoadParams, ar: LoadArith[T], in: RecipeInputs[T]): T = {
    import in._
    val vf = p.velocityFormats
    val af = p.accelerationFormats
    val sc = p.cordic.outputFormat
    val kf = p.constantFormat
    val r = p.productRounding
    def f(node: String) = p.fmt(node)
    val dd2Shift = Integer.numberOfTrailingZeros(p.model.dd2Weight)
    require(1 << dd2Shift == p.model.dd2Weight, s"dd2 weight ${p.model.dd2Weight} is not a power of two")

    val v12 = ar.add(d1, vf(0), d2, vf(1), 0, f("v12"))
    val a2 = ar.add(dd1, af(0), dd2, af(1), dd2Shift, f("a2"))
    val a12 = ar.add(dd1, af(0), dd2, af(1), 0, f("a12"))
    val a3 = ar.add(a12, f("a12"), dd3, af(2), 0, f("a3"))
    val sq1 = ar.mul(d1, vf(0), d1, vf(0), f("sq1"), r)
    val sq12 = ar.mul(v12, f("v12"), v12, f("v12"), f("sq12"), r)
    val kA = ar.constant(p.constA, kf)
    val kB = ar.constant(p.constB, kf)
    val kC = ar.constant(p.constC, kf)
    val kD = ar.constant(p.constD, kf)
    val u1 = ar.mul(kA, kf, dd1, af(0), f("u1"), r)
    val u2 = ar.mul(kB, kf, a2, f("a2"), f("u2"), r)
    val u3 = ar.mul(kA, kf, sq1, f("sq1"), f("u3"), r)
    val u4 = ar.mul(kB, kf, sq12, f("sq12"), f("u4"), r)
    val u5 = ar.mul(kC, kf, a3, f("a3"), f("u5"), r)
    val p1 = ar.mul(u1, f("u1"), c23, sc, f("p1"), r)
    val p2 = ar.mul(u2, f("u2"), c3, sc, f("p2"), r)
    val p3 = ar.mul(u3, f("u3"), s23, sc, f("p3"), r)
    val p4 = ar.mul(u4, f("u4"), s3, sc, f("p4"), r)
    val p6 = ar.mul(kD, kf, s123, sc, f("p6"), r)
    val s12 = ar.add(p1, f("p1"), p2, f("p2"), 0, f("s12"))
    val s34 = ar.add(p3, f("p3"), p4, f("p4"), 0, f("s34"))
    val s56 = ar.add(p6, f("p6"), u5, f("u5"), 0, f("s56"))
    val s1234 = ar.add(s12, f("s12"), s34, f("s34"), 0, f("s1234"))
    ar.add(s1234, f("s1234"), s56, f("s56"), 0, f("total"))
  }
}

/** Integer semantics of [[LoadArith]]: exact, with every result checked against its proven format. */
object IntArith extends LoadArith[BigInt] {
  private def checked(v: BigInt, out: FixedFormat, what: String): BigInt = {
    require(out.contains(v), s"LoadDatapathModel: $what = $v outside its proven format $out")
    v
  }
  def add(a: BigInt, aFmt: FixedFormat, b: BigInt, bFmt: FixedFormat, bShift: Int, out: FixedFormat): BigInt = {
    require(aFmt.fracBits == bFmt.fracBits && out.fracBits == aFmt.fracBits, s"add: fraction bits differ ($aFmt, $bFmt -> $out)")
    checked(a + (b << bShift), out, "sum")
  }
  def mul(a: BigInt, aFmt: FixedFormat, b: BigInt, bFmt: FixedFormat, out: FixedFormat, rounding: Rounding): BigInt = {
    val drop = aFmt.fracBits + bFmt.fracBits - out.fracBits
    checked(FixedFormat.shiftRound(a * b, drop, rounding), out, "product")
  }
  def constant(raw: BigInt, fmt: FixedFormat): BigInt = raw
}
