package reducerload.sim.text

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.testutil.Seeds

import java.math.{BigDecimal => JBigDecimal, MathContext, RoundingMode}
import scala.util.Random

/**
 * [[DoubleText]] against its rule, decided in BigDecimal arithmetic: the text reads back as the same double,
 * its digits are the shortest nearest decimal, and the layout is `Double.toString`'s (the same text wherever
 * JDK 17's `Double.toString` writes the shortest nearest digits).
 */
class DoubleTextSpec extends AnyFlatSpec {
  behavior of "DoubleText"

  private def digitsOf(text: String): Int = new JBigDecimal(text).stripTrailingZeros.precision

  /**
   * The rule's decimal for a finite non-zero double: the least length p at which some p-digit decimal rounds
   * to x, and of those the nearest to x (ties: even last digit). The candidates at each length: x rounded
   * half-even to p digits, and its p-digit neighbours (the nearest may fall outside the rounding interval
   * where the interval is narrower on one side, below a power of two).
   */
  private def shortestNearest(x: Double): JBigDecimal = {
    val exact = new JBigDecimal(x)
    (1 to 17).iterator
      .map { p =>
        val nearest = exact.round(new MathContext(p, RoundingMode.HALF_EVEN))
        val step = JBigDecimal.ONE.scaleByPowerOfTen(
          nearest.precision - nearest.scale - p
        ) // one unit in the p-th digit
        Seq(nearest, nearest.subtract(step), nearest.add(step))
          .filter(_.doubleValue == x)
          .sortBy(c => (c.subtract(exact).abs, c.unscaledValue.testBit(0)))(
            Ordering.Tuple2(Ordering[JBigDecimal], Ordering.Boolean)
          )
          .headOption
      }
      .collectFirst { case Some(c) => c }
      .get
  }

  /** Every promise of the rule for one double; returns whether JDK 17 wrote the same text. */
  private def check(x: Double): Boolean = {
    val text = DoubleText.format(x)
    val jdk = java.lang.Double.toString(x)
    assert(
      java.lang.Double.parseDouble(text).equals(x),
      s"$x: '$text' reads back as ${java.lang.Double.parseDouble(text)}"
    )
    if (x == 0 || x.isNaN || x.isInfinite || math.abs(x) < java.lang.Double.MIN_NORMAL) {
      assert(text == jdk, s"$x: '$text', Double.toString writes '$jdk'")
      true
    } else {
      assert(
        text.matches("-?(0|[1-9][0-9]*)\\.[0-9]+(E-?[1-9][0-9]*)?"),
        s"$x: '$text' is not in Double.toString's layout"
      )
      val plain = math.abs(x) >= 1e-3 && math.abs(x) < 1e7
      assert(plain != text.contains('E'), s"$x: '$text' plain/exponent layout")
      assert(!text.matches(".*[0-9]0E.*|.*\\.[0-9]*[1-9]0+$"), s"$x: '$text' has a trailing zero")
      val expected = shortestNearest(x)
      assert(
        new JBigDecimal(text).compareTo(expected) == 0,
        s"$x: '$text', the shortest nearest decimal is ${expected.toString}"
      )
      // JDK 17 differs only by writing more digits than needed, or digits that are not the nearest (JDK-4511638).
      if (text == jdk) true
      else {
        val exact = new JBigDecimal(x)
        def distance(t: String) = new JBigDecimal(t).subtract(exact).abs
        assert(
          digitsOf(jdk) > digitsOf(text) || (digitsOf(jdk) == digitsOf(text) && distance(jdk)
            .compareTo(distance(text)) > 0),
          s"$x: '$text', Double.toString writes '$jdk'"
        )
        false
      }
    }
  }

  it should "write the layout of Double.toString" in {
    Seq(
      0.0 -> "0.0",
      -0.0 -> "-0.0",
      1.0 -> "1.0",
      -3.0 -> "-3.0",
      30.0 -> "30.0",
      0.5 -> "0.5",
      12.5 -> "12.5",
      0.001 -> "0.001",
      9.999e-4 -> "9.999E-4",
      1e7 -> "1.0E7",
      9999999.0 -> "9999999.0",
      1.5e7 -> "1.5E7",
      -16.946797119039708 -> "-16.946797119039708",
      -4.066568202176768e-6 -> "-4.066568202176768E-6",
      1e23 -> "1.0E23",
      2e-3 -> "0.002",
      123456789.0 -> "1.23456789E8",
      Double.MaxValue -> "1.7976931348623157E308",
      java.lang.Double.MIN_NORMAL -> "2.2250738585072014E-308",
      Double.NaN -> "NaN",
      Double.PositiveInfinity -> "Infinity",
      Double.NegativeInfinity -> "-Infinity",
      Double.MinPositiveValue -> "4.9E-324",
      0.1 + 0.2 -> "0.30000000000000004"
    ).foreach { case (x, t) => assert(DoubleText.format(x) == t, s"$x"); check(x) }
    // Appends, as StringBuilder.append does.
    assert(DoubleText.append(new java.lang.StringBuilder("a,"), 2.5).toString == "a,2.5")
  }

  it should "write the shortest nearest decimal of every kind of double, as Double.toString does where that is shortest" in {
    val seed = Seeds("double-text", 19L)
    val rng = new Random(seed)
    val powers = (-1074 to 1023).flatMap { e =>
      val p = math.pow(2, e); Seq(p, math.nextUp(p), math.nextDown(p))
    } ++
      (-323 to 308).flatMap { e =>
        val p = s"1e$e".toDouble; Seq(p, math.nextUp(p), math.nextDown(p))
      }
    val integers =
      (0 until 2000).map(_ => (rng.nextLong() >> rng.nextInt(64)).toDouble) ++ (1 to 100).map(_.toDouble)
    val anyBits =
      (0 until 100000).map(_ => java.lang.Double.longBitsToDouble(rng.nextLong())).filterNot(_.isNaN)
    // What a replay writes: torques of newton-metres and their errors, down to rounding noise.
    val torques = (0 until 100000).map(_ => (rng.nextDouble() - 0.5) * math.pow(10, rng.nextInt(6)))
    val errors = (0 until 100000).map(_ => (rng.nextDouble() - 0.5) * math.pow(10, -3 - rng.nextInt(14)))
    val all = powers ++ integers ++ anyBits ++ torques ++ errors
    val sameAsJdk = all.count(check) + all.map(-_).count(check)
    println(
      s"DoubleText: ${all.size * 2} doubles (seed $seed): ${all.size * 2 - sameAsJdk} written other than (shorter or nearer than) JDK ${sys.props("java.specification.version")}'s Double.toString"
    )
  }
}
