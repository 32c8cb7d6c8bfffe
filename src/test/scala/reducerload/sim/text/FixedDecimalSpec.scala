package reducerload.sim.text

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.sim.model.FastFixed
import reducerload.testutil.Seeds

import scala.util.Random

/** [[FixedDecimal]]: the exact decimal of `code * 2^-fracBits`, by its documented rule, on both paths. */
class FixedDecimalSpec extends AnyFlatSpec {
  behavior of "FixedDecimal"

  private def text(code: Long, fracBits: Int): String =
    FixedDecimal.append(new java.lang.StringBuilder, code, fracBits).toString
  private def exact(code: BigInt, fracBits: Int): String =
    FixedDecimal.appendExact(new java.lang.StringBuilder, code, fracBits).toString

  /**
   * The rule, checked on the text alone: the exact value, plain, `.0` only for integers, no other trailing
   * zero.
   */
  private def obeysRule(t: String, code: BigInt, fracBits: Int): Boolean = {
    val c = new java.math.BigDecimal(code.bigInteger)
    val value =
      if (fracBits >= 0)
        c.divide(
          new java.math.BigDecimal(java.math.BigInteger.ONE.shiftLeft(fracBits))
        ) // exact: 2^-f terminates
      else c.multiply(new java.math.BigDecimal(java.math.BigInteger.ONE.shiftLeft(-fracBits)))
    val isInteger = value.signum == 0 || value.stripTrailingZeros.scale <= 0
    t.matches("-?(0|[1-9][0-9]*)\\.(0|[0-9]*[1-9])") && new java.math.BigDecimal(t).compareTo(value) == 0 &&
    t.startsWith("-") == (code < 0) && t.endsWith(".0") == isInteger
  }

  it should "write the documented examples" in {
    assert(text(25, 1) == "12.5")
    assert(text(-1, 20) == "-0.00000095367431640625")
    assert(text(0, 20) == "0.0")
    assert(text(-3L << 20, 20) == "-3.0")
    assert(text(12, 0) == "12.0")
    assert(text(1, 1) == "0.5")
    assert(text(-1, 1) == "-0.5")
    assert(text(3, 2) == "0.75")
    assert(text(1, 10) == "0.0009765625") // Double.toString: 9.765625E-4
    assert(text(Long.MaxValue, 0) == "9223372036854775807.0")
    assert(text(Long.MinValue, 0) == "-9223372036854775808.0")
    assert(text(Long.MinValue, 63) == "-1.0")
    assert(text(5, -2) == "20.0")
  }

  it should "give the exact value by its rule on the long and the BigDecimal path alike" in {
    val rng = new Random(Seeds("fixed-decimal", 81L))
    val edges = Seq(
      0L,
      1L,
      -1L,
      2L,
      -2L,
      9L,
      10L,
      -10L,
      Long.MaxValue,
      Long.MinValue,
      Long.MaxValue - 1,
      Long.MinValue + 1
    ) ++
      (0 until 63).flatMap(k => Seq(1L << k, -(1L << k), (1L << k) - 1, -(1L << k) + 1, (1L << k) + 1))
    val fracs = (-3 to 66)
    def check(code: Long, f: Int): Unit = {
      val t = text(code, f)
      assert(t == exact(BigInt(code), f), s"code $code, $f fraction bits")
      assert(obeysRule(t, BigInt(code), f), s"code $code, $f fraction bits: '$t'")
      assert(FixedDecimal.format(BigInt(code), f) == t)
    }
    edges.foreach(c => fracs.foreach(f => check(c, f)))
    (0 until 100000).foreach { _ =>
      val bits = 1 + rng.nextInt(64)
      val code = if (bits == 64) rng.nextLong() else rng.nextLong() >> (64 - bits)
      check(code, rng.nextInt(62))
    }
    // Codes beyond a long: the BigDecimal path, same rule.
    (0 until 2000).foreach { _ =>
      val code = BigInt(64 + rng.nextInt(64), rng) * (if (rng.nextBoolean()) 1 else -1)
      val f = rng.nextInt(100)
      val t = FixedDecimal.format(code, f)
      assert(obeysRule(t, code, f), s"code $code, $f fraction bits: '$t'")
    }
  }

  it should "read back as the double of the code, as the replay computes it" in {
    val rng = new Random(Seeds("fixed-decimal-double", 82L))
    (0 until 100000).foreach { _ =>
      val f = rng.nextInt(40)
      val code = rng.nextLong() >> (11 + rng.nextInt(50)) // at most 53 bits: the double is exact
      assert(text(code, f).toDouble == FastFixed.longToDouble(code, f), s"code $code, $f fraction bits")
    }
  }
}
