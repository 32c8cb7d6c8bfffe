package reducerload.pipeline

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.testutil.{Seeds, SimBackend}

import scala.util.Random
import reducerload.testutil.SimBackend.multiplierImpl // the JVM simulator builds the multipliers' Chisel twin

class PipelineSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "PipelinedMultiplier, ShiftAddMultiplier and MemoryDelay"

  private def signed(rng: Random, width: Int): BigInt = {
    val x = BigInt(width, rng.self)
    if (x.testBit(width - 1)) x - (BigInt(1) << width) else x
  }

  for ((wa, wb) <- Seq((18, 18), (26, 30), (35, 19), (4, 40)))
    it should s"multiply exactly, one product per clock, for $wa x $wb bits" in {
      val rng = new Random(Seeds(s"mul-$wa-$wb", 71L + wa))
      val extremes = Seq(-(BigInt(1) << (wa - 1)), (BigInt(1) << (wa - 1)) - 1, BigInt(0), BigInt(-1))
        .flatMap(a =>
          Seq(-(BigInt(1) << (wb - 1)), (BigInt(1) << (wb - 1)) - 1, BigInt(0), BigInt(-1)).map(a -> _)
        )
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
        pairs.zipWithIndex.foreach { case ((a, b), i) =>
          assert(observed(i + l) == a * b, s"$a * $b at sample $i")
        }
      }
    }

  it should "write a constant as its canonical signed digits: nonzero " +
    "digits never adjacent, summing to it" in {
      val rng = new Random(Seeds("signed-digits", 77L))
      val constants =
        Seq[BigInt](1, 2, 3, 5, 7, -1, -3, -4, -7, 0x5555, (BigInt(1) << 40) - 1, -(BigInt(1) << 40)) ++
          Seq.fill(2000)(BigInt(41, rng.self) - (BigInt(1) << 40)).filter(_ != 0)
      constants.foreach { c =>
        val d = ShiftAddMultiplier.digits(c)
        assert(d.map { case (k, s) => BigInt(s) << k }.sum == c && d.forall(x => x._2.abs == 1), s"$c: $d")
        assert(
          d.map(_._1).sliding(2).forall(ks => ks.size < 2 || ks(1) > ks(0) + 1),
          s"$c: adjacent digits in $d"
        )
      }
    }

  // A long mixed-sign constant, a negative one, a lone negative digit (negated at the end) and a two-digit
  // one.
  for (c <- Seq(BigInt(1258291), BigInt(-5033165), BigInt(-4), BigInt(3)))
    it should s"multiply by the constant $c exactly in shift-and-add logic, one product per clock" in {
      val width = 25
      val rng = new Random(Seeds(s"shift-add-$c", 78L))
      val xs = Seq(-(BigInt(1) << (width - 1)), (BigInt(1) << (width - 1)) - 1, BigInt(0), BigInt(-1)) ++ Seq
        .fill(SimBackend.scale(2000))(signed(rng, width))
      test(new ShiftAddMultiplier(width, c)).withAnnotations(SimBackend.annotations) { dut =>
        val l = ShiftAddMultiplier.latency(c)
        val observed = (xs ++ Seq.fill(l)(BigInt(0))).map { x =>
          dut.io.x.poke(x.S)
          val out = dut.io.product.peek().litValue
          dut.clock.step()
          out
        }
        xs.zipWithIndex.foreach { case (x, i) =>
          assert(
            observed(i + l) == ShiftAddMultiplier.model(x, c) && observed(i + l) == x * c,
            s"$x * $c at sample $i"
          )
        }
      }
    }

  // 3: the shortest, a buffer of two slots (the read pointer wraps every other clock)
  for (n <- Seq(3, 7))
    it should s"delay a stream by exactly $n clocks through block RAM" in {
      val rng = new Random(Seeds(s"memory-delay-$n", 75L))
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
