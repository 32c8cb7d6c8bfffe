package reducerload.load

import chisel3._
import reducerload.fixedpoint.{FixedFormat, FixedHw, Rounding}
import reducerload.pipeline.{MemoryDelay, PipelinedMultiplier}

/**
 * A signal and the cycle at which it holds the current sample (constants hold every sample).
 * `memoryDelayMinCycles`: delays at least this long go to block RAM (0: registers only).
 */
final case class Timed(value: SInt, at: Option[Int], memoryDelayMinCycles: Int = 0) {

  /** The value delayed to `cycle`: pipeline balancing by construction. */
  def alignedTo(cycle: Int): SInt = at match {
    case None => value
    case Some(t) =>
      require(cycle >= t, s"Timed: cannot read a value of cycle $t at earlier cycle $cycle")
      val n = cycle - t
      if (memoryDelayMinCycles > 0 && n >= memoryDelayMinCycles) MemoryDelay(value, n) else FixedHw.delay(value, n)
  }
}

/**
 * Hardware semantics of [[LoadArith]]: every operation is registered, operands are delayed to meet
 * (ASAP schedule), and each multiplier has registers on both sides so Quartus packs them into the
 * 18x18 blocks. Data registers have no reset: `valid` travels beside them and resets to low.
 */
final class TimedArith(multiplierLatency: Int, memoryDelayMinCycles: Int) extends LoadArith[Timed] {
  private def timed(v: SInt, at: Int) = Timed(v, Some(at), memoryDelayMinCycles)

  private def meet(a: Timed, b: Timed): Int = (a.at.toSeq ++ b.at.toSeq).maxOption.getOrElse(0)

  def add(a: Timed, aFmt: FixedFormat, b: Timed, bFmt: FixedFormat, bShift: Int, out: FixedFormat): Timed = {
    require(aFmt.fracBits == bFmt.fracBits && out.fracBits == aFmt.fracBits, s"add: fraction bits differ ($aFmt, $bFmt -> $out)")
    val t = meet(a, b)
    val sum = a.alignedTo(t).pad(out.width) + (b.alignedTo(t) << bShift).asSInt.pad(out.width)
    timed(FixedHw.delay(sum(out.width - 1, 0).asSInt, 1), t + 1)
  }

  def mul(a: Timed, aFmt: FixedFormat, b: Timed, bFmt: FixedFormat, out: FixedFormat, rounding: Rounding): Timed = {
    val t = meet(a, b)
    val drop = aFmt.fracBits + bFmt.fracBits - out.fracBits
    require(drop >= 0, s"mul: product has fewer fraction bits than $out")
    val product = FixedHw.delay(PipelinedMultiplier(a.alignedTo(t), b.alignedTo(t)), multiplierLatency - 1)
    val rounded = FixedHw.shiftRound(product, drop, rounding)
    val fitted = rounded(out.width - 1, 0).asSInt // proven range: the dropped top bits repeat the sign
    val done = t + TimedArith.mulLatency(aFmt.width, bFmt.width, multiplierLatency, rounding)
    rounding match {
      case Rounding.Truncate => timed(fitted, done) // bit selection only: no logic to register
      case _                 => timed(FixedHw.delay(fitted, 1), done)
    }
  }

  def constant(raw: BigInt, fmt: FixedFormat): Timed = Timed(raw.S(fmt.width.W), None)
}

object TimedArith {

  /** Clocks of one `mul`: the pipelined multiplier, extra registers, and the rounding adder if any. */
  def mulLatency(aWidth: Int, bWidth: Int, multiplierLatency: Int, rounding: Rounding): Int =
    PipelinedMultiplier.latency(aWidth, bWidth) + multiplierLatency - 1 + (if (rounding == Rounding.Truncate) 0 else 1)
}

/** The schedule of [[TimedArith]] without hardware: when each value is ready (None: a constant). */
final class LatencyArith(multiplierLatency: Int) extends LoadArith[Option[Int]] {
  private def meet(a: Option[Int], b: Option[Int]) = (a.toSeq ++ b.toSeq).maxOption.getOrElse(0)
  def add(a: Option[Int], aFmt: FixedFormat, b: Option[Int], bFmt: FixedFormat, bShift: Int, out: FixedFormat): Option[Int] =
    Some(meet(a, b) + 1)
  def mul(a: Option[Int], aFmt: FixedFormat, b: Option[Int], bFmt: FixedFormat, out: FixedFormat, rounding: Rounding): Option[Int] =
    Some(meet(a, b) + TimedArith.mulLatency(aFmt.width, bFmt.width, multiplierLatency, rounding))
  def constant(raw: BigInt, fmt: FixedFormat): Option[Int] = None
}
