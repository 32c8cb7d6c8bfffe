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
  override def desiredName = s"MemoryDelay_w${width}_d$cycles"
  val io = IO(new Bundle {
    val in = Input(UInt(width.W))
    val out = Output(UInt(width.W))
  })
  // no prefix from io.out on the pointer and the buffer: the module's Verilog as before the pointer was shared
  io.out := RegNext(chisel3.experimental.noPrefix(MemoryDelay.read(io.in, new DelayPointer(cycles))))
}

/**
 * The write pointer of block-RAM delays of `cycles` clocks, in the module it is made in: every such delay of
 * the module can share it ([[MemoryDelay.shared]]), one counter for all instead of one each. Resets to 0.
 * `kept`: a counter synthesis does not merge with an equal one, so that a pointer of its own can sit beside
 * its block RAM.
 */
final class DelayPointer(val cycles: Int, kept: Boolean = false) {
  require(
    cycles >= MemoryDelay.minCycles,
    s"MemoryDelay: use registers below ${MemoryDelay.minCycles} cycles, got $cycles"
  )

  /** Slots of the circular buffer ([[MemoryDelay.depth]]). */
  val depth: Int = MemoryDelay.depth(cycles)
  private def counter(init: Int): UInt = {
    val r = RegInit(init.U(log2Ceil(depth).max(1).W))
    if (kept) reducerload.fixedpoint.FixedHw.kept(r) else r
  }

  /**
   * The slot read this clock: the one written `depth - 1` clocks ago, the slot after `write`. A register of
   * its own, counting a clock ahead of `write`: the block RAM's address register (an M9K's, in the block)
   * takes it straight from a flip-flop. Computed from `write` (compare, increment, wrap) it was three LUT
   * levels before the route to the block RAM, the UR5's critical path (docs/timing-closure.md).
   */
  val next: UInt = counter(1 % depth)
  next := Mux(next === (depth - 1).U, 0.U, next + 1.U)

  /** The slot written this clock. */
  val write: UInt = counter(0)
  write := next
}

object MemoryDelay {

  /** The shortest delay in block RAM: the write, the synchronous read and the output register. */
  val minCycles: Int = 3

  /**
   * Slots of the circular buffer of a delay of `cycles` clocks: the synchronous read and the output register
   * give the last two clocks.
   */
  def depth(cycles: Int): Int = cycles - 1

  /**
   * The one rule of `datapath.memory-delay-min-cycles`: a delay of `cycles` clocks is in block RAM from
   * `memoryMinCycles` on (0: never), else in registers.
   */
  def inBlockRam(cycles: Int, memoryMinCycles: Int): Boolean =
    memoryMinCycles > 0 && cycles >= memoryMinCycles

  /** `x` delayed by `cycles` clocks: in block RAM or in registers ([[inBlockRam]]). */
  def balanced[T <: Data](x: T, cycles: Int, memoryMinCycles: Int): T =
    if (inBlockRam(cycles, memoryMinCycles)) apply(x, cycles)
    else reducerload.fixedpoint.FixedHw.delay(x, cycles)

  /** `x` written into a circular buffer at `pointer`, and the word read (one clock short of the delay). */
  private def read(x: UInt, pointer: DelayPointer): UInt = {
    val buffer = SyncReadMem(pointer.depth, UInt(x.getWidth.W))
    buffer.write(pointer.write, x)
    buffer.read(pointer.next, true.B)
  }

  /**
   * `x` delayed by `pointer.cycles` + `fabric` clocks in a block RAM of the current module, at a shared
   * pointer: the word read into an output register (the block RAM's own), then `fabric` registers in logic,
   * which the placer can put by the word's readers.
   */
  def shared[T <: Data](x: T, pointer: DelayPointer, fabric: Int = 0): T =
    (0 to fabric).foldLeft(read(x.asUInt, pointer))((v, _) => RegNext(v)).asTypeOf(x)

  /** `x` delayed by `cycles` clocks through a [[MemoryDelay]]. */
  def apply[T <: Data](x: T, cycles: Int): T = {
    val d = Module(new MemoryDelay(x.getWidth, cycles))
    d.io.in := x.asUInt
    d.io.out.asTypeOf(x)
  }
}
