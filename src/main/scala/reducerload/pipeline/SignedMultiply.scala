package reducerload.pipeline

import chisel3._
import chisel3.experimental.IntParam
import chisel3.util.{HasBlackBoxInline, ShiftRegister}

/**
 * Registered signed multiply: registers on both operands and on the product, written in Verilog (`product <=
 * $signed(a_r) * $signed(b_r)`). Latency [[SignedMultiply.latency]] clocks.
 *
 * Why a black box:
 *   - firtool 1.62 emits a FIRRTL signed multiply as an unsigned multiply of operands sign-extended to the
 *     product width (`{{17{a[17]}}, a} * {{18{b[17]}}, b}`, llvm/circt issue 4152); synthesis then builds a
 *     36x36 multiply from several DSP blocks plus fabric adders. A Verilog signed multiply of operands up to
 *     18 bits is one 18x18 block in signed mode.
 *   - The three registers belong to the multiplier alone, so Quartus packs them into the embedded
 *     multiplier's input and output registers on Cyclone IV, and the estimate's ECP5 proxy can map the module
 *     onto a registered MULT18X18D (tools/estimate/ecp5_primitives.v): the multiply itself never sits in a
 *     fabric register-to-register path.
 *
 * One parameterized Verilog module serves every width. The JVM simulator (treadle) cannot run Verilog: a
 * design built with [[MultiplierImpl.ChiselTwin]] (a constructor parameter of every module that multiplies)
 * has [[SignedMultiplyTwin]], the same registers and product in Chisel, instead.
 */
class SignedMultiply(val aWidth: Int, val bWidth: Int)
    extends BlackBox(Map("A_WIDTH" -> IntParam(aWidth), "B_WIDTH" -> IntParam(bWidth)))
    with HasBlackBoxInline {
  require(aWidth >= 1 && bWidth >= 1, s"SignedMultiply: operand widths must be >= 1, got $aWidth and $bWidth")
  val io = IO(new Bundle {
    val clock = Input(Clock())
    val a = Input(SInt(aWidth.W))
    val b = Input(SInt(bWidth.W))
    val product = Output(SInt((aWidth + bWidth).W))
  })
  override def desiredName = SignedMultiply.moduleName
  setInline(s"${SignedMultiply.moduleName}.sv", SignedMultiply.verilog)
}

/**
 * How a design's signed multiplies are built; a constructor parameter (implicit) of every module that
 * multiplies.
 */
sealed trait MultiplierImpl
object MultiplierImpl {

  /** The Verilog black box: emission, Verilator, Quartus. The default wherever no other is in scope. */
  case object VerilogBlackBox extends MultiplierImpl

  /** Its Chisel twin, for the JVM simulator (treadle), which cannot run Verilog. */
  case object ChiselTwin extends MultiplierImpl

  implicit val default: MultiplierImpl = VerilogBlackBox
}

object SignedMultiply {
  val moduleName = "SignedMultiply"

  /** Clocks from operands to product: operand registers, then the product register. */
  val latency = 2

  /** The black box's Verilog (firtool writes it after the design). */
  val verilog: String =
    s"""// Registered signed multiply: one 18x18 block with its input and output registers when both
       |// operands fit 18 bits. Latency $latency clocks. No reset: data registers only.
       |module $moduleName #(
       |  parameter A_WIDTH = 18,
       |  parameter B_WIDTH = 18
       |) (
       |  input                                    clock,
       |  input      signed [A_WIDTH-1:0]         a,
       |  input      signed [B_WIDTH-1:0]         b,
       |  output reg signed [A_WIDTH+B_WIDTH-1:0] product
       |);
       |  reg signed [A_WIDTH-1:0] a_r;
       |  reg signed [B_WIDTH-1:0] b_r;
       |  always @(posedge clock) begin
       |    a_r <= a;
       |    b_r <= b;
       |    product <= a_r * b_r;
       |  end
       |endmodule
       |""".stripMargin

  /** The exact signed product of `a` and `b` (`a.getWidth + b.getWidth` bits), [[latency]] clocks later. */
  def apply(a: SInt, b: SInt)(implicit multiplierImpl: MultiplierImpl): SInt =
    if (multiplierImpl == MultiplierImpl.ChiselTwin) {
      val m = Module(new SignedMultiplyTwin(a.getWidth, b.getWidth))
      m.io.a := a
      m.io.b := b
      m.io.product
    } else {
      val m = Module(new SignedMultiply(a.getWidth, b.getWidth))
      m.io.clock := Module.clock
      m.io.a := a
      m.io.b := b
      m.io.product
    }
}

/** [[SignedMultiply]]'s behaviour in Chisel (operand registers, product register), for the JVM simulator. */
class SignedMultiplyTwin(aWidth: Int, bWidth: Int) extends Module {
  override def desiredName = s"SignedMultiplyTwin_${aWidth}x$bWidth"
  val io = IO(new Bundle {
    val a = Input(SInt(aWidth.W))
    val b = Input(SInt(bWidth.W))
    val product = Output(SInt((aWidth + bWidth).W))
  })
  // Operand registers, then the product register: SignedMultiply.latency clocks in all.
  private val operandDelay = SignedMultiply.latency - 1
  io.product := RegNext(ShiftRegister(io.a, operandDelay) * ShiftRegister(io.b, operandDelay))
}
