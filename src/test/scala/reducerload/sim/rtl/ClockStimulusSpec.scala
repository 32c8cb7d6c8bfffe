package reducerload.sim.rtl

import org.scalatest.flatspec.AnyFlatSpec

/** The stimulus record's word in the harness's file (VerilatorHarness.cppSource reads the same bits). */
class ClockStimulusSpec extends AnyFlatSpec {
  behavior of "ClockStimulus"

  it should "keep every flag and the read address through its file word" in {
    val cases = for {
      offer <- Seq(false, true)
      reset <- Seq(false, true)
      snapshot <- Seq(false, true)
      clear <- Seq(false, true)
      read <- Seq(None, Some(0), Some(1), Some(Int.MaxValue))
    } yield ClockStimulus(123456789012L, offer, reset, snapshot, clear, read)
    cases.foreach(c => assert(ClockStimulus.fromWord(c.cycle, c.word) == c))
    assert(
      ClockStimulus(0, offer = true).word == 1 && ClockStimulus(0, read = Some(3)).word == (16L | (3L << 32))
    )
  }

  it should "refuse a negative clock or read address" in {
    assertThrows[IllegalArgumentException](ClockStimulus(-1))
    assertThrows[IllegalArgumentException](ClockStimulus(0, read = Some(-1)))
  }
}
