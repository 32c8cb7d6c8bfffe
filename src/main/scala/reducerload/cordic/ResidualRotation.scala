package reducerload.cordic

import chisel3._
import chisel3.util._
import reducerload.fixedpoint.FixedHw
import reducerload.pipeline.{MemoryDelay, MultiplierImpl, SignedMultiply}

/**
 * The multiply-based end of the residual architecture, three steps:
 *   1. zr = z * 2pi (one 18x18 multiplier; z in turns -> radians on the x/y scale, truncated); 2. x zr and y
 *      zr with x, y truncated to the bits that matter against |zr| (one 18x18 each); 3. x' = x - y zr, y' = y
 *      + x zr (first order; its gain and angle error are in the error bound). Each multiply is a
 *      [[SignedMultiply]] (registered operands and product), the rotation one register; the state waits for
 *      the products in a [[MemoryDelay]] (block RAM) and a register after it, the valid bit in registers.
 */
class ResidualRotation(p: CordicParams)(implicit multiplierImpl: MultiplierImpl) extends Module {
  require(p.residual, "ResidualRotation: CordicParams.architecture must be residual")
  override def desiredName = s"ResidualRotation_${p.tag}"
  private val zWidth = p.zFormat(p.iterations).width
  val io = IO(new Bundle {
    val in = Input(Valid(new CordicStateBundle(p, zWidth)))
    val out = Output(Valid(new CordicStateBundle(p, zWidth)))
  })
  private val f = p.xyFormat.fracBits
  private val drop = f - p.residualOperandFracBits

  // Step 1: z to radians.
  private val zrFull = SignedMultiply(io.in.bits.z, p.twoPiRaw.S((p.twoPiRaw.bitLength + 1).W))
  private val zr = (zrFull >> (p.zFracBits + p.twoPiFracBits - f))(p.zrFormat.width - 1, 0).asSInt
  // x, y wait for zr (narrow registers, only the bits the products use) and for the products (the
  // whole state, in block RAM: four clocks of two wide words would cost an LE per bit and clock).
  private val xTrunc = FixedHw.delay((io.in.bits.x >> drop).asSInt, SignedMultiply.latency)
  private val yTrunc = FixedHw.delay((io.in.bits.y >> drop).asSInt, SignedMultiply.latency)
  private val vector = Wire(new CordicVectorBundle(p))
  vector.x := io.in.bits.x
  vector.y := io.in.bits.y
  vector.quadrant := io.in.bits.quadrant
  // The block RAM's output (its own output register) crossed the die to the rotation's adders and limited
  // the Z1's clock (docs/timing-closure.md): a fabric register after it, near the adders, takes the last clock.
  private val waited = RegNext(MemoryDelay(vector, ResidualRotation.stateDelayInMemory))

  // Step 2: the two products.
  private val xzr = SignedMultiply(xTrunc, zr)
  private val yzr = SignedMultiply(yTrunc, zr)

  // Step 3: rotate.
  private val w = p.xyFormat.width
  private val out = Reg(new CordicStateBundle(p, zWidth))
  out.x := (waited.x - (yzr >> p.residualOperandFracBits).asSInt)(w - 1, 0).asSInt
  out.y := (waited.y + (xzr >> p.residualOperandFracBits).asSInt)(w - 1, 0).asSInt
  out.z := 0.S
  out.quadrant := waited.quadrant
  io.out.bits := out
  io.out.valid := ShiftRegister(io.in.valid, p.residualLatency, false.B, true.B)
}

object ResidualRotation {

  /** Clocks the state waits in block RAM for the products, a fabric register taking the last of them. */
  val stateDelayInMemory: Int = 2 * SignedMultiply.latency - 1
}
