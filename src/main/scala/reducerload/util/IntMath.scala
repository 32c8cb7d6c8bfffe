package reducerload.util

/** Integer arithmetic the schedulers and the resource counts share. */
object IntMath {

  /** `a / b` rounded up, for a >= 0 and b > 0: the blocks, slots or copies `a` items need `b` to a block. */
  def ceilDiv(a: Int, b: Int): Int = (a + b - 1) / b
}
