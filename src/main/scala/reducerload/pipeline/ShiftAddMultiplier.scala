package reducerload.pipeline

import chisel3._
import reducerload.fixedpoint.FixedHw

/**
 * Multiply by a constant code in logic elements, no multiplier block (`schedule.constant-multiplies =
 * shift-add`): the constant's canonical signed digits (non-adjacent form: the fewest nonzero digits, no two
 * adjacent) select shifted copies of `x`, summed by a registered adder tree, one level per clock. The result
 * is the exact product `x * constant`, as from a multiplier.
 */
class ShiftAddMultiplier(xWidth: Int, constant: BigInt) extends Module {
  require(xWidth >= 2, s"ShiftAddMultiplier: an operand of $xWidth bits")
  require(constant != 0, "ShiftAddMultiplier: a multiply by zero is folded away, not built")
  override def desiredName =
    s"ShiftAddMultiplier_${xWidth}_${if (constant < 0) "m" else ""}${constant.abs.toString(16)}"
  val io = IO(new Bundle {
    val x = Input(SInt(xWidth.W))
    val product = Output(SInt(ShiftAddMultiplier.productWidth(xWidth, constant).W))
  })
  private val w = ShiftAddMultiplier.productWidth(xWidth, constant)

  import ShiftAddMultiplier.Partial
  private def add(a: Partial, b: Partial): Partial = (a.negated, b.negated) match {
    case (false, false) => Partial(a.value +% b.value, negated = false)
    case (true, true)   => Partial(a.value +% b.value, negated = true)
    case (false, true)  => Partial(a.value -% b.value, negated = false)
    case (true, false)  => Partial(b.value -% a.value, negated = false)
  }
  private def level(xs: Seq[Partial]): Seq[Partial] = xs
    .grouped(2)
    .map {
      case Seq(a, b) => add(a, b)
      case Seq(a)    => a
    }
    .map(p => p.copy(value = FixedHw.delay(p.value, 1)))
    .toSeq
  @scala.annotation.tailrec
  private def tree(xs: Seq[Partial]): Partial = if (xs.size == 1) xs.head else tree(level(xs))

  private val terms = ShiftAddMultiplier.digits(constant).map { case (shift, sign) =>
    Partial((io.x.pad(w) << shift)(w - 1, 0).asSInt, sign < 0)
  }
  // One term alone still takes its register, as every level does.
  private val sum =
    if (terms.size == 1) terms.head.copy(value = FixedHw.delay(terms.head.value, 1)) else tree(terms)
  io.product := (if (sum.negated) FixedHw.delay(-%(sum.value), 1) else sum.value)

  private def -%(x: SInt): SInt = (0.S(w.W) -% x)(w - 1, 0).asSInt
}

object ShiftAddMultiplier {

  /**
   * A partial sum, and whether it stands for its negative (same-sign pairs keep the sign; a mixed pair
   * subtracts).
   */
  private final case class Partial(value: SInt, negated: Boolean)

  /**
   * Canonical signed digits of `c` (non-adjacent form), least significant first: (bit position, +1 or -1).
   */
  def digits(c: BigInt): Seq[(Int, Int)] =
    Iterator
      .iterate((c, 0)) { case (n, k) => ((n - digit(n)) >> 1, k + 1) }
      .takeWhile(_._1 != 0)
      .collect { case (n, k) if digit(n) != 0 => (k, digit(n)) }
      .toSeq
  private def digit(n: BigInt): Int = if (!n.testBit(0)) 0 else if ((n & 3) == 1) 1 else -1

  /** Bits of the exact product of an `xWidth`-bit operand and `c`. */
  def productWidth(xWidth: Int, c: BigInt): Int = xWidth + c.abs.bitLength + 1

  /**
   * Clocks from operand to product: one per adder-tree level (at least one), and one to negate when every
   * digit is negative.
   */
  def latency(c: BigInt): Int = {
    val d = digits(c)
    math.max(1, 32 - Integer.numberOfLeadingZeros(d.size - 1)) + (if (d.forall(_._2 < 0)) 1 else 0)
  }

  /**
   * Adders the tree takes (nonzero digits - 1, and the negation when every digit is negative), for reports.
   */
  def adders(c: BigInt): Int = { val d = digits(c); d.size - 1 + (if (d.forall(_._2 < 0)) 1 else 0) }

  /** The product as built, for the bit-accurate model: exact. */
  def model(x: BigInt, c: BigInt): BigInt = x * c

  def apply(x: SInt, constant: BigInt): SInt = {
    val m = Module(new ShiftAddMultiplier(x.getWidth, constant))
    m.io.x := x
    m.io.product
  }
}
