package reducerload.graph

import org.scalatest.flatspec.AnyFlatSpec

/**
 * Where a held value is read from: its first register, a chain of registers, or a block-RAM delay from
 * `datapath.memory-delay-min-cycles` clocks on (the RTL check of the taps is every shared registers design of
 * ArmDatapathSpec).
 */
class HeldTapsSpec extends AnyFlatSpec {
  behavior of "HeldTaps"

  it should "read a value from registers within an interval and from block RAM from the threshold on" in {
    // ready in cycle 10 at 17 clocks per sample; read in cycles 10, 26 (stage 0), 27 (stage 1), 80 (stage 4)
    val taps = HeldTaps(17, 10, Seq(10, 26, 27, 80), memoryMinCycles = 4)
    assert(taps == HeldTaps(chain = 0, delayed = Seq(1, 4)))
    assert(taps.registerBits(28) == 28)
  }

  it should "keep short stretches in registers below the threshold and everything with threshold 0" in {
    // 3 clocks per sample, threshold 7: stage 2 (6 clocks) in registers, stage 3 (9 clocks) in block RAM
    assert(HeldTaps(3, 5, Seq(7, 11, 14), memoryMinCycles = 7) == HeldTaps(chain = 2, delayed = Seq(3)))
    assert(HeldTaps(3, 5, Seq(7, 11, 14), memoryMinCycles = 0) == HeldTaps(chain = 3, delayed = Nil))
    assert(HeldTaps(3, 5, Seq(7, 11, 14), memoryMinCycles = 0).registerBits(10) == 40)
  }
}
