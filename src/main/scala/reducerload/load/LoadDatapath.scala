package reducerload.load

import chisel3._
import chisel3.util._
import reducerload.cordic.CordicSinCos
import reducerload.fixedpoint.{FixedHw, Rounding}

/**
 * Joint-3 reducer load: a sample in (`valid`, taken when `ready`), a `Valid` load out exactly
 * `latency` cycles later. Three CORDIC pipelines compute sin/cos of t3, t2+t3 and t1+t2+t3 (angle
 * sums in the binary-angle domain wrap modulo one turn, as they should); the velocity and
 * acceleration products run beside them and are delayed to meet the sin/cos values.
 *
 * With `cordicUnits = 1` one CORDIC pipeline takes the three angles on three consecutive clocks
 * and its results leave on three consecutive clocks; the recipe's schedule absorbs the offsets.
 * `ready` is then low for the two clocks after a sample is taken (one sample every 3 clocks); with
 * three units it is always high. A sample offered while `ready` is low is not taken.
 *
 * Inputs beyond the declared ranges are clamped to the range and raise `outOfRange` on that
 * sample's output; nothing downstream can overflow (formats are derived from the ranges).
 */
class LoadDatapath(val p: LoadParams) extends Module {
  override def desiredName = s"LoadDatapath_${p.model.name}"
  val io = IO(new Bundle {
    val in = Flipped(Decoupled(new LoadInput(p)))
    val out = Valid(new LoadOutput(p))
  })

  private val shared = p.cordicUnits == 1

  // Cycle 1: input registers (held while a shared unit works through the three angles).
  private val accept = io.in.valid && io.in.ready
  private val in = if (shared) RegEnable(io.in.bits, accept) else RegNext(io.in.bits)
  private val inValid = RegNext(accept, false.B)

  // Cycle 2: clamp each velocity and acceleration to its declared range and register its
  // out-of-range flag; cycle 3: OR the six flags. In one clock, the compares and the OR chain
  // were the critical path.
  private def clamp(x: SInt, limit: BigInt): (SInt, Bool) = {
    val (value, outside) = FixedHw.clamp(x, -limit, limit, x.getWidth)
    (FixedHw.delay(value, 1), RegNext(outside))
  }
  private val velocities = Seq(in.d1, in.d2, in.d3).zip(p.velocityLimitRaw).map { case (x, l) => clamp(x, l) }
  private val accelerations = Seq(in.dd1, in.dd2, in.dd3).zip(p.accelerationLimitRaw).map { case (x, l) => clamp(x, l) }
  private val d = velocities.map(_._1)
  private val dd = accelerations.map(_._1)
  private val outOfRange = RegNext((velocities ++ accelerations).map(_._2).reduce(_ || _))
  private val clampedAt = LoadDatapath.operandCycle

  // Cycle 2: first angle sum.
  private val t1 = RegNext(in.t1)
  private val t3 = RegNext(in.t3)
  private val t23 = RegNext(in.t2 +% in.t3) // modulo one turn: wrap is the angle arithmetic, not an overflow
  private val valid2 = RegNext(inValid, false.B)
  io.in.ready := (if (shared) !(inValid || valid2) else true.B)

  // Cycle 2 -> CORDIC inputs (each CORDIC registers its input): t1+t2+t3 = (t2+t3) + t1.
  private val angles = Seq(t3, t23, t23 +% t1)
  private val Seq(t3At, t23At, t123At) = LoadDatapath.trigCycles(p)
  private val Seq(cs3, cs23, cs123) =
    if (!shared) angles.map { angle =>
      val c = Module(new CordicSinCos(p.cordic))
      c.io.in.valid := valid2
      c.io.in.bits := angle
      c.io.out.bits
    }
    else {
      // The angle registers hold the sample for cycles 2, 3 and 4 (ready was low): one angle each.
      val valid3 = RegNext(valid2, false.B)
      val valid4 = RegNext(valid3, false.B)
      val c = Module(new CordicSinCos(p.cordic))
      c.io.in.valid := valid2 || valid3 || valid4
      c.io.in.bits := Mux(valid3, angles(1), Mux(valid4, angles(2), angles(0)))
      Seq.fill(3)(c.io.out.bits) // the same wires, holding each angle's result one clock after the other
    }
  private def trig(out: SInt, at: Int) = Timed(out, Some(at), p.memoryDelayMinCycles)

  private val total = LoadRecipe(
    p,
    new TimedArith(p.multiplierLatency, p.memoryDelayMinCycles),
    RecipeInputs(
      d1 = Timed(d(0), Some(clampedAt), p.memoryDelayMinCycles),
      d2 = Timed(d(1), Some(clampedAt), p.memoryDelayMinCycles),
      dd1 = Timed(dd(0), Some(clampedAt), p.memoryDelayMinCycles),
      dd2 = Timed(dd(1), Some(clampedAt), p.memoryDelayMinCycles),
      dd3 = Timed(dd(2), Some(clampedAt), p.memoryDelayMinCycles),
      c23 = trig(cs23.cos, t23At),
      c3 = trig(cs3.cos, t3At),
      s23 = trig(cs23.sin, t23At),
      s3 = trig(cs3.sin, t3At),
      s123 = trig(cs123.sin, t123At)
    )
  )
  private val totalAt = total.at.getOrElse(throw new IllegalStateException("the load cannot be a constant"))

  // Output stage: round half up to the output format; the range proof makes saturation unreachable.
  private val rounded = FixedHw.shiftRound(total.value, p.internalFracBits - p.outputFracBits, Rounding.HalfUp)
  private val (load, saturated) = FixedHw.saturate(rounded, p.outputFormat)

  /** Cycles from a sample on `io.in` to its load on `io.out`. */
  val latency: Int = totalAt + 1
  require(latency == LoadDatapath.latency(p), s"LoadDatapath: built latency $latency differs from the predicted ${LoadDatapath.latency(p)}")

  private val outBits = Reg(new LoadOutput(p))
  outBits.load := load
  outBits.outOfRange := FixedHw.delay(outOfRange, totalAt - LoadDatapath.outOfRangeCycle) || saturated
  io.out.bits := outBits
  io.out.valid := ShiftRegister(valid2, latency - 2, false.B, true.B)

}

object LoadDatapath {

  /** Cycle at which the clamped velocities and accelerations and the angle sums are in registers. */
  val operandCycle: Int = 2

  /** Cycle at which the OR of the six out-of-range flags is in its register. */
  val outOfRangeCycle: Int = operandCycle + 1

  /** Cycles at which sin/cos of t3, t2+t3 and t1+t2+t3 leave the CORDIC unit(s): in turn when it is shared. */
  def trigCycles(p: LoadParams): Seq[Int] = {
    val first = operandCycle + p.cordic.latency
    if (p.cordicUnits == 1) Seq(first, first + 1, first + 2) else Seq.fill(3)(first)
  }

  /** Latency without elaborating: the recipe's schedule (same rules as the hardware), then the output register. */
  def latency(p: LoadParams): Int = {
    val in: Option[Int] = Some(operandCycle)
    val Seq(t3, t23, t123) = trigCycles(p).map(Some(_))
    LoadRecipe(p, new LatencyArith(p.multiplierLatency), RecipeInputs(in, in, in, in, in, t23, t3, t23, t3, t123)).get + 1
  }
}
