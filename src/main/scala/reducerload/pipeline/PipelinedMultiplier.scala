package reducerload.pipeline

import chisel3._
import reducerload.fixedpoint.FixedHw

/**
 * Signed multiply wider than one 18x18 block, pipelined: the operands are cut into 17-bit unsigned low chunks
 * and a signed top chunk (each fits an 18x18 signed multiplier), every 18x18 block has registers on its
 * operands and its product ([[SignedMultiply]]), and the shifted partial products are summed by a registered
 * adder tree, one level per clock. The result is the exact full-width product.
 */
class PipelinedMultiplier(aWidth: Int, bWidth: Int)(implicit multiplierImpl: MultiplierImpl) extends Module {
  require(aWidth >= 2 && bWidth >= 2, s"PipelinedMultiplier: operands of $aWidth and $bWidth bits")
  override def desiredName = s"PipelinedMultiplier_${aWidth}x$bWidth"
  val io = IO(new Bundle {
    val a = Input(SInt(aWidth.W))
    val b = Input(SInt(bWidth.W))
    val product = Output(SInt((aWidth + bWidth).W))
  })

  /** Latency in clocks from operands to product. */
  val latency: Int = PipelinedMultiplier.latency(aWidth, bWidth)

  /** (chunk as an 18-bit-or-narrower signed value, its bit offset). */
  private def chunks(x: SInt, width: Int): Seq[(SInt, Int)] = {
    val n = PipelinedMultiplier.chunkCount(width)
    (0 until n).map { i =>
      val lo = i * PipelinedMultiplier.chunkBits
      if (i == n - 1) (x(width - 1, lo).asSInt, lo) // the top chunk carries the sign
      else (x(lo + PipelinedMultiplier.chunkBits - 1, lo).zext, lo) // unsigned low chunk, zero-extended
    }
  }

  private val w = aWidth + bWidth
  private val partials: Seq[SInt] =
    for ((ac, ao) <- chunks(io.a, aWidth); (bc, bo) <- chunks(io.b, bWidth))
      yield (SignedMultiply(ac, bc).pad(w) << (ao + bo)).asSInt

  // Synthesis trims each adder to the bits above the partial products' zero low bits.
  private def sumTree(xs: Seq[SInt]): SInt =
    if (xs.size == 1) xs.head
    else
      sumTree(
        xs.grouped(2)
          .map {
            case Seq(x, y) =>
              FixedHw.delay((x +% y)(w - 1, 0).asSInt, 1) // exact: the full product fits w bits
            case Seq(x) => FixedHw.delay(x(w - 1, 0).asSInt, 1)
          }
          .toSeq
      )

  io.product := sumTree(partials)(w - 1, 0).asSInt
}

object PipelinedMultiplier {
  val chunkBits = 17

  def chunkCount(width: Int): Int = if (width <= 18) 1 else 1 + (width - 18 + chunkBits - 1) / chunkBits

  /** The registered partial products, then one clock per adder-tree level. */
  def latency(aWidth: Int, bWidth: Int): Int = {
    val partials = chunkCount(aWidth) * chunkCount(bWidth)
    SignedMultiply.latency + (if (partials <= 1) 0 else 32 - Integer.numberOfLeadingZeros(partials - 1))
  }

  /** Number of 18x18 blocks. */
  def blocks(aWidth: Int, bWidth: Int): Int = chunkCount(aWidth) * chunkCount(bWidth)

  def apply(a: SInt, b: SInt)(implicit multiplierImpl: MultiplierImpl): SInt = {
    val m = Module(new PipelinedMultiplier(a.getWidth, b.getWidth))
    m.io.a := a
    m.io.b := b
    m.io.product
  }
}
