package reducerload.fixedpoint

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.testutil.SimBackend

/** Every constant around a 5-bit range, compared both ways: one output pair per constant. */
class ConstCompare(width: Int, val constants: Seq[BigInt]) extends Module {
  val io = IO(new Bundle {
    val x = Input(SInt(width.W))
    val greater = Output(Vec(constants.size, Bool()))
    val less = Output(Vec(constants.size, Bool()))
  })
  constants.zipWithIndex.foreach { case (c, i) =>
    io.greater(i) := FixedHw.greaterThan(io.x, c)
    io.less(i) := FixedHw.lessThan(io.x, c)
  }
}

/** `FixedHw.roundSaturate` of one 8-bit signal for each (drop, output format) case. */
class RoundSaturate(width: Int, val cases: Seq[(Int, FixedFormat)]) extends Module {
  val io = IO(new Bundle {
    val x = Input(SInt(width.W))
    val code = Output(Vec(cases.size, SInt(cases.map(_._2.width).max.W)))
    val saturated = Output(Vec(cases.size, Bool()))
  })
  cases.zipWithIndex.foreach { case ((drop, to), i) =>
    val (code, saturated) = FixedHw.roundSaturate(io.x, drop, to)
    io.code(i) := code.pad(io.code(i).getWidth)
    io.saturated(i) := saturated
  }
}

class FixedHwSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "FixedHw constant comparisons"

  it should "equal integer > and < for every value and every constant of a " +
    "5-bit signal, in range and beyond" in {
      val width = 5
      val constants = (-20 to 20).map(BigInt(_)) // beyond -16..15 on both sides too
      test(new ConstCompare(width, constants)).withAnnotations(SimBackend.annotations) { dut =>
        val bad = (-16 to 15).flatMap { x =>
          dut.io.x.poke(x.S)
          constants.zipWithIndex.flatMap { case (c, i) =>
            val (g, l) = (dut.io.greater(i).peek().litToBoolean, dut.io.less(i).peek().litToBoolean)
            if (g != (x > c) || l != (x < c)) Some(s"x=$x c=$c: greater $g, less $l") else None
          }
        }
        assert(bad.isEmpty, bad.take(10).mkString("\n"))
        println(
          s"[fixedpoint] constant comparisons: 32 values x ${constants.size} constants, both " +
            s"directions, all equal to integer compare"
        )
      }
    }

  behavior of "FixedHw.roundSaturate"

  it should "equal the model's rescale (half up) then saturate for every 8-bit value, " +
    "narrow and wide formats, every drop" in {
      val width = 8
      val formats = Seq(
        FixedFormat(0, 1),
        FixedFormat(1, 1),
        FixedFormat(2, 1),
        FixedFormat(3, 0),
        FixedFormat(4, 1),
        FixedFormat(5, 2),
        FixedFormat(7, 0)
      )
      val cases = for (drop <- -1 to 4; f <- formats) yield (drop, f)
      test(new RoundSaturate(width, cases)).withAnnotations(SimBackend.annotations) { dut =>
        val bad = (-128 to 127).flatMap { x =>
          dut.io.x.poke(x.S)
          cases.zipWithIndex.flatMap { case ((drop, f), i) =>
            val (want, wantFlag) =
              FixedFormat.saturate(FixedFormat.rescale(BigInt(x), drop, Rounding.HalfUp), f)
            val (got, gotFlag) = (dut.io.code(i).peek().litValue, dut.io.saturated(i).peek().litToBoolean)
            if (got != want || gotFlag != wantFlag)
              Some(s"x=$x drop=$drop to=$f: got $got/$gotFlag, model $want/$wantFlag")
            else None
          }
        }
        assert(bad.isEmpty, bad.take(10).mkString("\n"))
        println(
          s"[fixedpoint] roundSaturate: 256 values x ${cases.size} (drop, " +
            s"format) cases, all equal to the model"
        )
      }
    }
}
