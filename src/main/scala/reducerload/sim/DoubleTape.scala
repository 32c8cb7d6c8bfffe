package reducerload.sim

import reducerload.dynamics.Num

import scala.collection.mutable.ArrayBuffer

/**
 * A double-precision formula written over [[Num]] (the references: `Rnea.torques`,
 * `Joint3Load.torque`), recorded once as a list of operations on numbered slots and then evaluated
 * per sample without allocation. The same IEEE operations on the same operands in the same order as
 * the formula on `Num.doubleNum` (which folds nothing), so every result is bit-identical
 * (ReplayArraysSpec). The caller fills in input `k` at slot `inputSlots(k)` before each [[run]].
 */
final class DoubleTape private (val inputSlots: Array[Int], slots: Int, constSlot: Array[Int], constValue: Array[Double],
  kind: Array[Int], dst: Array[Int], left: Array[Int], right: Array[Int], val outputSlots: Array[Int]) {
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
    val (kind, dst, left, right) = (this.kind, this.dst, this.left, this.right) // locals: no field checks in the loop
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
   * Record `formula`: it gets a [[Num]] over slot numbers and a maker of input slots (input k is the
   * k-th made), and returns its output slots.
   */
  def record(formula: (Num[Int], () => Int) => Seq[Int]): DoubleTape = {
    var slots = 0
    val inputSlots = ArrayBuffer.empty[Int]
    val constSlot, kind, dst, left, right = ArrayBuffer.empty[Int]
    val constValue = ArrayBuffer.empty[Double]
    def op(k: Int, a: Int, b: Int): Int = {
      require(a >= 0 && a < slots && b >= 0 && b < slots, s"DoubleTape: operand slot out of range ($a, $b of $slots)")
      kind += k; dst += slots; left += a; right += b
      slots += 1
      slots - 1
    }
    val num = new Num[Int] {
      def const(x: Double): Int = { constSlot += slots; constValue += x; slots += 1; slots - 1 }
      def plus(a: Int, b: Int): Int = op(Plus, a, b)
      def minus(a: Int, b: Int): Int = op(Minus, a, b)
      def times(a: Int, b: Int): Int = op(Times, a, b)
      def negate(a: Int): Int = op(Negate, a, a)
    }
    val input = () => { inputSlots += slots; slots += 1; slots - 1 }
    val outputs = formula(num, input).toArray
    new DoubleTape(inputSlots.toArray, slots, constSlot.toArray, constValue.toArray, kind.toArray, dst.toArray, left.toArray, right.toArray, outputs)
  }
}
