package reducerload.load

import reducerload.config.DatapathParams
import reducerload.testutil.CompiledParams
import reducerload.config.LoadParams
import reducerload.arm.LoadReference
import reducerload.robot.RobotParams
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.arm.ArmSample
import reducerload.cordic.CordicParams
import reducerload.testutil.{Golden, Seeds}

import scala.util.Random

/** The double reference and the bit-accurate model, without a simulator. */
class LoadModelSpec extends AnyFlatSpec {
  behavior of "LoadReference and the joint-3 model"

  it should "agree with the independent golden loads (Pinocchio RNEA and both closed forms) to 1e-9 N·m" in {
    Golden.all.foreach { t =>
      t.samples.indices.foreach { i =>
        val s = t.samples(i)
        val exact = LoadReference.torque(t.robot, LoadModel.Exact, s)
        val paper = LoadReference.torque(t.robot, LoadModel.PaperEq6, s)
        assert(math.abs(exact - t.rnea(i)) < 1e-9, s"${t.name} row $i: exact $exact vs rnea ${t.rnea(i)}")
        assert(math.abs(exact - t.exact(i)) < 1e-9, s"${t.name} row $i: exact $exact vs golden ${t.exact(i)}")
        assert(math.abs(paper - t.paper(i)) < 1e-9, s"${t.name} row $i: paper $paper vs golden ${t.paper(i)}")
      }
    }
  }

  it should "differ between the paper's formula and the exact one by m3 l2 l3 dd2 cos t3" in {
    val r = RobotParams()
    val rng = new Random(Seeds("paper-minus-exact", 31L))
    (0 until 1000).foreach { _ =>
      val s = LoadChecks.randomSample(r, rng)
      val diff = LoadReference.torque(r, LoadModel.PaperEq6, s) - LoadReference.torque(r, LoadModel.Exact, s)
      assert(math.abs(diff - r.m3 * r.l2 * r.l3 * s.qdd(1) * math.cos(s.q(2))) < 1e-9)
    }
  }

  it should "stay within the derived bound on the golden traces for both presets" in {
    for ((name, p) <- LoadParams.presets; t <- Golden.all) {
      val m = new LoadChecks.Joint3Model(p)
      val err = t.samples.map(s => math.abs(m.evaluate(s) - LoadReference.torque(p.robot, p.model, s))).max
      println(
        f"[load-model] $name%-8s ${t.name}%-13s max |model - double| $err%.3e N·m, bound ${p.errorBound}%.3e"
      )
      assert(err <= p.errorBound)
    }
  }

  it should "never exceed the derived bound over seeded random robots, generator settings and inputs" in {
    val rng = new Random(Seeds("random-robots", 32L))
    def pick(lo: Double, hi: Double) = lo + (hi - lo) * rng.nextDouble()
    val configs = 150
    val worst = (0 until configs).map { _ =>
      val robot = RobotParams(
        m3 = pick(5, 20),
        l1 = pick(0.2, 0.6),
        l2 = pick(0.2, 0.6),
        l3 = pick(0.2, 0.6),
        g = pick(0, 9.81),
        maxVelocity = Seq.fill(3)(pick(0.5, 3)),
        maxAcceleration = Seq.fill(3)(pick(1, 10))
      )
      val bits = 12 + rng.nextInt(14)
      val p = LoadParams(
        robot = robot,
        model = if (rng.nextBoolean()) LoadModel.Exact else LoadModel.PaperEq6,
        cordic = CordicParams(
          angleBits = bits + 2,
          outputBits = bits + 2,
          iterations = bits,
          guardBits = 1 + rng.nextInt(5),
          angleGuardBits = 3 + rng.nextInt(3)
        ),
        datapath = DatapathParams(
          velocityFracBits = 10 + rng.nextInt(12),
          accelerationFracBits = 10 + rng.nextInt(12),
          constantFracBits = 12 + rng.nextInt(14),
          internalFracBits = 12 + rng.nextInt(8),
          outputFracBits = 8 + rng.nextInt(4)
        )
      )
      val m = new LoadChecks.Joint3Model(p)
      (0 until 100).map { _ =>
        val s = LoadChecks.randomSample(robot, rng)
        val err = math.abs(m.evaluate(s) - LoadReference.torque(robot, p.model, s))
        assert(err <= p.errorBound, s"$p: error $err exceeds the bound ${p.errorBound} at $s")
        err / p.errorBound
      }.max
    }
    println(
      f"[load-model] $configs random configurations x 100 samples: worst error / bound = ${worst.max}%.3f"
    )
  }

  it should "clamp inputs beyond the declared ranges, flag them, and never flag in-range inputs" in {
    val p = LoadParams.default
    val m = new LoadChecks.Joint3Model(p)
    val rng = new Random(Seeds("clamp", 33L))
    (0 until 2000).foreach { _ =>
      val s = LoadChecks.randomSample(p.robot, rng)
      assert(!m.evaluate(m.encode(s)).outOfRange.exists(identity), s"in-range sample flagged: $s")
    }
    // Every extreme of every input, both signs: flagged, and the load is that of the clamped sample.
    for (i <- 3 until 9; sign <- Seq(-1.0, 1.0)) {
      val base = LoadChecks.randomSample(p.robot, rng).toSeq.toArray
      val limit = if (i < 6) p.robot.maxVelocity(i - 3) else p.robot.maxAcceleration(i - 6)
      val clamped = base.clone(); clamped(i) = sign * limit
      val beyond = base.clone(); beyond(i) = sign * limit * 1.25
      val outBeyond = m.evaluate(m.encode(ArmSample.fromRow(beyond.toSeq)))
      val outClamped = m.evaluate(m.encode(ArmSample.fromRow(clamped.toSeq)))
      assert(
        outBeyond.outOfRange.exists(identity),
        s"input ${Joint3Columns.names(i)} = ${beyond(i)} not flagged"
      )
      assert(!outClamped.outOfRange.exists(identity), s"input ${Joint3Columns.names(i)} at its limit flagged")
      assert(outBeyond.tau == outClamped.tau, s"input ${Joint3Columns.names(i)} beyond range is not clamped")
    }
  }
}
