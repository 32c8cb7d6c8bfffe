package reducerload.sim.model

import reducerload.dynamics.Num

import scala.collection.mutable
import scala.collection.mutable.ArrayBuffer

/**
 * A double-precision formula written over [[Num]] (the references: `Rnea.torques`, `Joint3Load.torque`),
 * recorded once as a list of operations on numbered slots and then evaluated per sample without allocation.
 * The same IEEE operations on the same operands in the same order as the formula on `Num.doubleNum`, which
 * folds nothing (the tape folds only what IEEE arithmetic makes exact: operations on constants, x * 1 and x *
 * -1), so every result is bit-identical (ReplayArraysSpec). The caller fills in input `k` at slot
 * `inputSlots(k)` before each [[run]].
 */
final class DoubleTape private (
    val inputSlots: Array[Int],
    slots: Int,
    constSlot: Array[Int],
    constValue: Array[Double],
    kind: Array[Int],
    dst: Array[Int],
    left: Array[Int],
    right: Array[Int],
    val outputSlots: Array[Int]
) {
  import DoubleTape._

  /** A work array with the constants in place; one per thread. */
  def scratch(): Array[Double] = {
    val v = new Array[Double](slots)
    var c = 0
    while (c < constSlot.length) { v(constSlot(c)) = constValue(c); c += 1 }
    v
  }

  /** Every operation, in the recorded order, on `v` (from [[scratch]], with the inputs filled in). */
  def run(v: Array[Double]): Unit = {
    val (kind, dst, left, right) =
      (this.kind, this.dst, this.left, this.right) // locals: no field checks in the loop
    val n = kind.length
    var i = 0
    while (i < n) {
      val a = v(left(i))
      v(dst(i)) = (kind(i): @annotation.switch) match {
        case Plus  => a + v(right(i))
        case Minus => a - v(right(i))
        case Times => a * v(right(i))
        case _     => -a
      }
      i += 1
    }
  }

  /** Output `k` after [[run]]. */
  def output(v: Array[Double], k: Int): Double = v(outputSlots(k))
}

object DoubleTape {
  private final val Plus = 0
  private final val Minus = 1
  private final val Times = 2
  private final val Negate = 3

  /**
   * Record `formula`: it gets a [[Num]] over slot numbers and a maker of input slots (input k is the k-th
   * made), and returns its output slots.
   */
  def record(formula: (Num[Int], () => Int) => Seq[Int]): DoubleTape = {
    var slots = 0
    val inputSlots = ArrayBuffer.empty[Int]
    val constSlot, kind, dst, left, right = ArrayBuffer.empty[Int]
    val constValue = ArrayBuffer.empty[Double]
    def op(k: Int, a: Int, b: Int): Int = {
      require(
        a >= 0 && a < slots && b >= 0 && b < slots,
        s"DoubleTape: operand slot out of range ($a, $b of $slots)"
      )
      kind += k; dst += slots; left += a; right += b
      slots += 1
      slots - 1
    }
    // Folded only where IEEE arithmetic is exact whatever the operand: an operation on two constants
    // (computed once, the same operation), x * 1 = x and x * -1 = -x.
    val constants = mutable.HashMap.empty[Int, Double]
    def constOf(a: Int): Option[Double] = constants.get(a)
    def isBits(a: Int, x: Double) = constOf(a).exists(c =>
      java.lang.Double.doubleToRawLongBits(c) == java.lang.Double.doubleToRawLongBits(x)
    )
    val num: Num[Int] = new Num[Int] {
      def const(x: Double): Int = {
        constSlot += slots; constValue += x; constants(slots) = x; slots += 1; slots - 1
      }
      private def both(a: Int, b: Int, f: (Double, Double) => Double)(otherwise: => Int): Int =
        (constOf(a), constOf(b)) match {
          case (Some(x), Some(y)) => const(f(x, y))
          case _                  => otherwise
        }
      def plus(a: Int, b: Int): Int = both(a, b, _ + _)(op(Plus, a, b))
      def minus(a: Int, b: Int): Int = both(a, b, _ - _)(op(Minus, a, b))
      def times(a: Int, b: Int): Int = both(a, b, _ * _) {
        if (isBits(a, 1.0)) b
        else if (isBits(b, 1.0)) a
        else if (isBits(a, -1.0)) op(Negate, b, b)
        else if (isBits(b, -1.0)) op(Negate, a, a)
        else op(Times, a, b)
      }
      def negate(a: Int): Int = constOf(a).fold(op(Negate, a, a))(x => const(-x))
    }
    val input = () => { inputSlots += slots; slots += 1; slots - 1 }
    val outputs = formula(num, input).toArray
    new DoubleTape(
      inputSlots.toArray,
      slots,
      constSlot.toArray,
      constValue.toArray,
      kind.toArray,
      dst.toArray,
      left.toArray,
      right.toArray,
      outputs
    )
  }
}
