package reducerload.pipeline

import chisel3._
import chisel3.util._

/**
 * A fixed delay of `cycles` clocks in block RAM (an M9K in Quartus) instead of `cycles * width` registers. A
 * circular buffer of depth `cycles - 1`: each clock writes the input at the write pointer and reads the next
 * slot, which holds the value written `cycles - 1` clocks ago; the read address never equals the write
 * address, so read-under-write behaviour does not matter. The memory's synchronous read and an output
 * register supply the last cycles of delay; the output register keeps RAM read paths out of the multipliers
 * the delayed values usually feed.
 *
 * The pointer resets to 0 (a defined state after reset); the contents need none: outputs during the first
 * `cycles` clocks after reset belong to samples whose valid bit was cleared.
 */
class MemoryDelay(width: Int, cycles: Int) extends Module {
  require(width >= 1, s"MemoryDelay: width must be >= 1, got $width")
  require(cycles >= 3, s"MemoryDelay: use registers below 3 cycles, got $cycles")
  override def desiredName = s"MemoryDelay_w${width}_d$cycles"
  val io = IO(new Bundle {
    val in = Input(UInt(width.W))
    val out = Output(UInt(width.W))
  })
  private val depth = cycles - 1
  private val last = (depth - 1).U
  private val write = RegInit(0.U(log2Ceil(depth).max(1).W))
  private val next = Mux(write === last, 0.U, write + 1.U)
  write := next
  private val buffer = SyncReadMem(depth, UInt(width.W))
  buffer.write(write, io.in)
  io.out := RegNext(buffer.read(next, true.B))
}

object MemoryDelay {

  /** `x` delayed by `cycles` clocks: in block RAM from `memoryMinCycles` on (0: never), else in registers. */
  def balanced[T <: Data](x: T, cycles: Int, memoryMinCycles: Int): T =
    if (memoryMinCycles > 0 && cycles >= memoryMinCycles) apply(x, cycles)
    else reducerload.fixedpoint.FixedHw.delay(x, cycles)

  /** `x` delayed by `cycles` clocks through a [[MemoryDelay]]. */
  def apply[T <: Data](x: T, cycles: Int): T = {
    val d = Module(new MemoryDelay(x.getWidth, cycles))
    d.io.in := x.asUInt
    d.io.out.asTypeOf(x)
  }
}
