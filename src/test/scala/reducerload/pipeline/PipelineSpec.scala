package reducerload.pipeline

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.testutil.{Seeds, SimBackend}

import scala.util.Random
import reducerload.testutil.SimBackend.multiplierImpl // the JVM simulator builds the multipliers' Chisel twin

class PipelineSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "PipelinedMultiplier and MemoryDelay"

  private def signed(rng: Random, width: Int): BigInt = {
    val x = BigInt(width, rng.self)
    if (x.testBit(width - 1)) x - (BigInt(1) << width) else x
  }

  for ((wa, wb) <- Seq((18, 18), (26, 30), (35, 19), (4, 40))) {
    it should s"multiply exactly, one product per clock, for $wa x $wb bits" in {
      val rng = new Random(Seeds(s"mul-$wa-$wb", 71L + wa))
      val extremes = Seq(-(BigInt(1) << (wa - 1)), (BigInt(1) << (wa - 1)) - 1, BigInt(0), BigInt(-1))
        .flatMap(a => Seq(-(BigInt(1) << (wb - 1)), (BigInt(1) << (wb - 1)) - 1, BigInt(0), BigInt(-1)).map(a -> _))
      val pairs = extremes ++ Seq.fill(SimBackend.scale(3000))((signed(rng, wa), signed(rng, wb)))
      test(new PipelinedMultiplier(wa, wb)).withAnnotations(SimBackend.annotations) { dut =>
        val l = dut.latency
        assert(l == PipelinedMultiplier.latency(wa, wb))
        val observed = (pairs ++ Seq.fill(l)((BigInt(0), BigInt(0)))).map { case (a, b) =>
          dut.io.a.poke(a.S); dut.io.b.poke(b.S)
          val out = dut.io.product.peek().litValue
          dut.clock.step()
          out
        }
        pairs.zipWithIndex.foreach { case ((a, b), i) => assert(observed(i + l) == a * b, s"$a * $b at sample $i") }
      }
    }
  }

  it should "delay a stream by exactly n clocks through block RAM" in {
    val n = 7
    val rng = new Random(Seeds("memory-delay", 75L))
    val xs = Seq.fill(SimBackend.scale(2000))(BigInt(20, rng.self))
    test(new MemoryDelay(20, n)).withAnnotations(SimBackend.annotations) { dut =>
      val observed = xs.map { x =>
        dut.io.in.poke(x.U)
        val o = dut.io.out.peek().litValue
        dut.clock.step()
        o
      }
      xs.indices.drop(n).foreach(i => assert(observed(i) == xs(i - n), s"cycle $i"))
    }
  }
}
