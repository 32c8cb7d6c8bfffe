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

class FixedHwSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "FixedHw constant comparisons"

  it should "equal integer > and < for every value and every constant of a 5-bit signal, in range and beyond" in {
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
      println(s"[fixedpoint] constant comparisons: 32 values x ${constants.size} constants, both directions, all equal to integer compare")
    }
  }
}
