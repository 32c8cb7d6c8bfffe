package reducerload.load

import reducerload.config.DatapathParams
import reducerload.testutil.CompiledParams
import reducerload.config.LoadParams
import reducerload.arm.LoadReference
import reducerload.robot.RobotParams
import circt.stage.ChiselStage
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.cordic.{CordicArchitecture, CordicParams}
import reducerload.fixedpoint.Rounding
import reducerload.testutil.Seeds

import scala.util.{Failure, Random, Success, Try}

/**
 * Random generator and robot configurations, valid and not: each either builds and meets its derived bound on
 * random inputs, or is refused at elaboration with a message naming the parameter.
 */
class ParamFuzzSpec extends AnyFlatSpec {
  behavior of "LoadParams under fuzzed configurations"

  private val parameterNames = Seq("CordicParams.", "robot.", "datapath.", "declared ranges")

  it should "build and meet the bound, or refuse naming the parameter, for 300 random configurations" in {
    val rng = new Random(Seeds("param-fuzz", 61L))
    // Mostly plausible values, with a few wild ones (negative, zero, NaN, huge) among them.
    def pick(lo: Int, hi: Int) =
      if (rng.nextInt(40) == 0) Seq(-1, 0, 1000)(rng.nextInt(3)) else lo + rng.nextInt(hi - lo + 1)
    def real(lo: Double, hi: Double) = if (rng.nextInt(60) == 0)
      Seq(-1.0, 0.0, Double.NaN, 1e9)(rng.nextInt(4))
    else lo + (hi - lo) * rng.nextDouble()
    val outcomes = (0 until 300).map { i =>
      Try {
        val bits = 8 + rng.nextInt(23)
        LoadParams(
          robot = RobotParams(
            m3 = real(1, 30),
            l1 = real(0.1, 1),
            l2 = real(0.1, 1),
            l3 = real(0.1, 1),
            g = real(0, 10),
            maxVelocity = Seq.fill(3)(real(0.1, 5)),
            maxAcceleration = Seq.fill(3)(real(0.5, 20))
          ),
          model = if (rng.nextBoolean()) LoadModel.Exact else LoadModel.PaperEq6,
          cordic = CordicParams(
            angleBits = bits + pick(-2, 4),
            outputBits = bits + pick(-2, 2),
            iterations = pick(4, bits),
            guardBits = pick(1, 6),
            angleGuardBits = pick(2, 6),
            outputRounding = Rounding.all(rng.nextInt(2)),
            iterationsPerStage = pick(1, 3),
            architecture = CordicArchitecture.all(rng.nextInt(2))
          ),
          datapath = DatapathParams(
            velocityFracBits = pick(8, 24),
            accelerationFracBits = pick(8, 24),
            constantFracBits = pick(10, 26),
            internalFracBits = pick(8, 22),
            outputFracBits = pick(6, 16),
            productRounding = Rounding.all(rng.nextInt(2)),
            multiplierLatency = pick(1, 3),
            memoryDelayMinCycles = Seq(0, 3, 4, 8)(rng.nextInt(4))
          )
        )
      }.flatMap(p => Try { p.arm.analysis; p }) match {
        case Failure(e: IllegalArgumentException) =>
          assert(
            parameterNames.exists(e.getMessage.contains),
            s"configuration $i refused without naming a parameter: ${e.getMessage}"
          )
          assert(!e.getMessage.contains("\n"))
          "refused"
        case Failure(e) => fail(s"configuration $i: ${e.getClass.getName}: ${e.getMessage}")
        case Success(p) =>
          val m = new LoadChecks.Joint3Model(p)
          (0 until 40).foreach { _ =>
            val s = LoadChecks.randomSample(p.robot, rng)
            val err = math.abs(m.evaluate(s) - LoadReference.torque(p.robot, p.model, s))
            assert(err <= p.errorBound, s"configuration $i: error $err exceeds its bound ${p.errorBound}")
          }
          if (i % 30 == 0)
            ChiselStage.convert(new reducerload.arm.ArmDatapath(p.arm)) // elaborates without exceptions
          "built"
      }
    }
    val counts = outcomes.groupBy(identity).view.mapValues(_.size).toMap
    println(
      s"[fuzz] parameters: 300 configurations, ${counts.getOrElse("built", 0)} built and met their bound, ${counts.getOrElse("refused", 0)} refused naming the parameter"
    )
    assert(counts.getOrElse("built", 0) >= 20 && counts.getOrElse("refused", 0) >= 20)
  }
}
