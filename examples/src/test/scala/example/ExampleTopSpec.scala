package example

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.api.{ReducerLoad, Robot}
import reducerload.arm.{ArmOutputCodes, ArmSample}
import reducerload.pipeline.MultiplierImpl

import scala.collection.mutable.ArrayBuffer
import scala.util.Random

class ExampleTopSpec extends AnyFlatSpec with ChiselScalatestTester {
  // treadle, chiseltest's JVM simulator, runs the multiplies' Chisel twin (it cannot run Verilog).
  implicit val multiplierImpl: MultiplierImpl = MultiplierImpl.ChiselTwin

  // Every joint of the built-in planar arm, at the `smallest` preset's arithmetic; no bus wrapper: the
  // datapath's own ready/valid ports, for a Chisel parent.
  private val core = ReducerLoad(Robot.Planar3, "--preset", "smallest", "--bus", "none")

  behavior of "ExampleTop"

  it should "return the library model's torques for every sample, in order, and count them" in {
    val seed = sys.env.get("EXAMPLE_SEED").map(_.toLong).getOrElse(32L)
    println(
      s"ExampleTopSpec: seed $seed; ${core.moduleName}, latency ${core.latency}, ${core.clocksPerSample} clocks per sample"
    )
    val rng = new Random(seed)
    val arm = core.compiled.arm
    def within(limits: Seq[Double]) = limits.map(l => rng.between(-l, l)).toIndexedSeq
    val samples = IndexedSeq.fill(24)(
      ArmSample(
        IndexedSeq.fill(arm.chain.size)(rng.between(-math.Pi, math.Pi)),
        within(arm.maxVelocity),
        within(arm.maxAcceleration)
      )
    )
    val codes = samples.map(core.model.encode)
    val expected = codes.map(core.model.evaluate)

    test(new ExampleTop(core)) { dut =>
      val got = ArrayBuffer.empty[ArmOutputCodes]
      var sent = 0
      var cycles = 0
      val limit = samples.size * core.clocksPerSample + core.latency + 50
      while (got.size < samples.size && cycles < limit) {
        // Random bubbles on the input: the FIFO and the core's ready take care of the rest.
        val offer = sent < samples.size && rng.nextInt(4) != 0
        dut.io.in.valid.poke(offer.B)
        if (offer) {
          val c = codes(sent)
          c.angles.zipWithIndex.foreach { case (v, j) => dut.io.in.bits.q(j).poke(v.U) }
          c.velocities.zipWithIndex.foreach { case (v, j) => dut.io.in.bits.qd(j).poke(v.S) }
          c.accelerations.zipWithIndex.foreach { case (v, j) => dut.io.in.bits.qdd(j).poke(v.S) }
        }
        if (offer && dut.io.in.ready.peek().litToBoolean) sent += 1
        if (dut.io.out.valid.peek().litToBoolean)
          got += ArmOutputCodes(
            dut.io.out.bits.tau.map(_.peek().litValue).toIndexedSeq,
            dut.io.out.bits.outOfRange.map(_.peek().litToBoolean).toIndexedSeq
          )
        dut.clock.step()
        cycles += 1
      }
      assert(got.size == samples.size, s"${got.size} of ${samples.size} results in $cycles cycles")
      got.zip(expected).zipWithIndex.foreach { case ((g, e), k) => assert(g == e, s"sample $k") }
      dut.io.results.expect(samples.size.U)
      val torques = core.model.torques(got.last)
      println(s"ExampleTopSpec: last sample's torques ${torques.map(t => f"$t%.4f").mkString(", ")} N·m")
    }
  }

  it should "refuse bad settings with the command line's one-line message" in {
    val e = intercept[reducerload.util.InputError](ReducerLoad(Robot.Ur5))
    assert(e.getMessage.contains("--max-acceleration"), e.getMessage)
  }
}
