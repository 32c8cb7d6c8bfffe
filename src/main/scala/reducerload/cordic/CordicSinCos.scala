package reducerload.cordic

import chisel3._
import chisel3.util._
import reducerload.pipeline.MultiplierImpl

/** [[CordicSinCos]]'s ports: a binary angle in, (cos, sin) out, both valid-qualified. */
class CordicSinCosIO(p: CordicParams) extends Bundle {
  val in = Flipped(Valid(UInt(p.angleBits.W)))
  val out = Valid(new SinCos(p))
}

/**
 * Pipelined CORDIC sin/cos: a `Valid` binary angle in, a `Valid` (cos, sin) out exactly `latency` cycles
 * later, one angle per clock with no stall. Gain K is folded into the start vector. Stages: input register,
 * table registers (with a table: the read, the block RAM's output register, and the route register with
 * `p.tableRouteRegister`), `p.stageIterations.size` rotation stages, the residual rotation (residual
 * architecture), output stage.
 */
class CordicSinCos(val p: CordicParams)(implicit multiplierImpl: MultiplierImpl) extends Module {
  override def desiredName = s"CordicSinCos_${p.tag}"
  val io = IO(new CordicSinCosIO(p))

  /** Cycles from an angle on `io.in` to its (cos, sin) on `io.out`. */
  val latency: Int = p.latency

  // Input register: the angle usually arrives from an adder or from pins.
  private val angle = RegNext(io.in.bits)
  private val angleValid = RegNext(io.in.valid, false.B)

  private val pre = Module(new QuadrantPreprocessor(p))
  pre.io.angle := angle

  private val folded = Wire(Valid(new CordicStateBundle(p, p.zFormat(p.firstIteration).width)))
  folded.valid := angleValid
  folded.bits := pre.io.state

  // With a table: the ROM read is registered, then its data once more (the RAM block's output
  // register), so the first adder sees a register and not a block-RAM access time; with the route
  // register, once more in logic, which the placer can put beside the first stage.
  private val start =
    if (p.tableBits == 0) folded
    else {
      val r = Wire(Valid(new CordicStateBundle(p, p.zFormat(p.firstIteration).width)))
      r.valid := ShiftRegister(folded.valid, p.tableLatency, false.B, true.B)
      r.bits := ShiftRegister(folded.bits, p.tableLatency)
      r
    }

  private val rotated = p.stageIterations.foldLeft(start) { (in, iterations) =>
    val stage = Module(new CordicStage(p, iterations))
    stage.io.in := in
    stage.io.out
  }

  private val finished =
    if (!p.residual) rotated
    else {
      val residual = Module(new ResidualRotation(p))
      residual.io.in := rotated
      residual.io.out
    }

  private val post = Module(new QuadrantPostprocessor(p))
  post.io.in := finished
  io.out := post.io.out
}
