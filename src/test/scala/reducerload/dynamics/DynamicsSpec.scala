package reducerload.dynamics

import reducerload.config.DatapathParams
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.arm.{ArmModel, ArmParams, ArmSample}
import reducerload.cordic.CordicParams
import reducerload.graph.{GraphReference, Op}
import reducerload.arm.LoadReference
import reducerload.load.LoadModel
import reducerload.robot.RobotParams
import reducerload.robot.Planar3
import reducerload.testutil.{Golden, Seeds}

import scala.util.Random

/**
 * The dynamics compiler without hardware: RNEA against independent references (Pinocchio's golden traces, the
 * closed form, Euler-Lagrange on random arms), the graph's double interpretation against RNEA, and the
 * bit-accurate model within its derived bound.
 */
class DynamicsSpec extends AnyFlatSpec {
  behavior of "Rnea and the dynamics graph"

  /** A random arm's datapath at fixed, modest word lengths (the bounds are then far from zero). */
  private def randomArm(
      chain: reducerload.robot.SerialChain,
      vmax: Seq[Double],
      amax: Seq[Double],
      composeParallelAxes: Boolean = false
  ): ArmParams = ArmParams(
    chain,
    vmax,
    amax,
    cordic =
      CordicParams(angleBits = 20, outputBits = 20, iterations = 16, guardBits = 3, angleGuardBits = 4),
    datapath = DatapathParams(
      velocityFracBits = 16,
      accelerationFracBits = 14,
      constantFracBits = 18,
      internalFracBits = 18,
      outputFracBits = 16,
      composeParallelAxes = composeParallelAxes
    )
  )

  it should "give the planar arm's joint-3 torque of Pinocchio's golden traces and of the closed form" in {
    val chain = Planar3.chain()
    val worst = Golden.all.flatMap { t =>
      t.samples.zip(t.rnea).map { case (s, pin) =>
        val tau = Rnea.reference(chain, s.q, s.qd, s.qdd)
        math.max(
          math.abs(tau(2) - pin),
          math.abs(tau(2) - LoadReference.torque(RobotParams(), LoadModel.Exact, s))
        )
      }
    }.max
    println(
      f"[dynamics] planar3: max |rnea tau3 - (pinocchio, closed form)| = $worst%.2e N·m over ${Golden.all.map(_.samples.size).sum} samples"
    )
    assert(worst < 1e-9)
  }

  it should "agree with Euler-Lagrange on random serial arms of 2 to 7 joints" in {
    val rng = new Random(Seeds("random-arms-lagrange", 31L))
    val worst = (2 to 7).flatMap { n =>
      (0 until 6).map { _ =>
        val chain = RandomChains.chain(rng, n)
        val (q, qd, qdd) = RandomChains.sample(rng, Seq.fill(n)(3.0), Seq.fill(n)(10.0))
        val a = Rnea.reference(chain, q, qd, qdd)
        val b = LagrangeReference.torques(chain, q, qd, qdd)
        a.zip(b).map { case (x, y) => math.abs(x - y) / (1 + math.abs(y)) }.max
      }
    }.max
    println(f"[dynamics] random arms: max relative |rnea - lagrange| = $worst%.2e")
    assert(worst < 1e-6)
  }

  it should "fold robot constants: the graph in doubles equals RNEA in doubles, with fewer operations than generic RNEA" in {
    val rng = new Random(Seeds("graph-vs-rnea", 32L))
    (2 to 7).foreach { n =>
      val chain = RandomChains.chain(rng, n)
      val graph = ArmParams.rneaGraph(chain, Seq.fill(n)(3.0), Seq.fill(n)(10.0))._1
      assert(!graph.ops.exists {
        case Op.Mul(a, b) => graph(a).isInstanceOf[Op.Const] && graph(b).isInstanceOf[Op.Const];
        case _            => false
      })
      (0 until 20).foreach { _ =>
        val (q, qd, qdd) = RandomChains.sample(rng, Seq.fill(n)(3.0), Seq.fill(n)(10.0))
        val a = Rnea.reference(chain, q, qd, qdd)
        val b = GraphReference.outputs(graph, q, qd, qdd)
        a.zip(b).foreach { case (x, y) =>
          assert(math.abs(x - y) <= 1e-9 * (1 + math.abs(x)), s"$n joints: rnea $x, graph $y")
        }
      }
    }
    val planar = ArmParams.rneaGraph(Planar3.chain(), Seq.fill(3)(3.0), Seq.fill(3)(10.0))._1.counts
    println(s"[dynamics] planar3 graph: $planar")
    assert(planar.sinCos == 3)
  }

  it should "cross runs of parallel axes in one rotation by the summed angle: the same torques in doubles, " +
    "on the graph and in the bit-accurate model within its bound" in {
      val ur5 = reducerload.compiler.Compiler.arm(reducerload.testutil.ArmGolden.of("ur5").head.config).chain
      assert(Rnea.parallelRuns(ur5) == Seq(0 to 0, 1 to 3, 4 to 4, 5 to 5))
      assert(Rnea.parallelRuns(Planar3.chain()) == Seq(0 to 2))
      val rng = new Random(Seeds("parallel-axes", 34L))
      val runs = (2 to 7).flatMap { n =>
        val chain = RandomChains.parallelChain(rng, n)
        val vmax = Seq.fill(n)(3.0)
        val amax = Seq.fill(n)(10.0)
        val p = randomArm(chain, vmax, amax, composeParallelAxes = true)
        val model = new ArmModel(p)
        (0 until 20).foreach { _ =>
          val (q, qd, qdd) = RandomChains.sample(rng, vmax, amax)
          val ref = Rnea.reference(chain, q, qd, qdd)
          val states = q.indices.map(j => JointState(math.cos(q(j)), math.sin(q(j)), qd(j), qdd(j)))
          val summed = (span: Range) => CosSin(math.cos(span.map(q).sum), math.sin(span.map(q).sum))
          val composed = Rnea.torques(chain, states, summed = Some(summed))
          val graph = GraphReference.outputs(p.graph, q, qd, qdd)
          val hw = model.evaluate(ArmSample(q, qd, qdd))
          ref.indices.foreach { j =>
            val tol = 1e-9 * (1 + math.abs(ref(j)))
            assert(
              math.abs(composed(j) - ref(j)) <= tol,
              s"$n joints, joint ${j + 1}: composed ${composed(j)}"
            )
            assert(math.abs(graph(j) - ref(j)) <= tol, s"$n joints, joint ${j + 1}: graph ${graph(j)}")
            assert(
              math.abs(hw(j) - ref(j)) <= p.errorBounds(j),
              s"$n joints, joint ${j + 1}: model ${hw(j)}, reference ${ref(j)}, bound ${p.errorBounds(j)}"
            )
          }
        }
        Rnea.parallelRuns(chain).filter(_.size > 1)
      }
      println(s"[dynamics] random arms with parallel axes: runs ${runs.mkString(", ")}")
      assert(runs.exists(_.size > 2))
    }

  it should "keep the bit-accurate model within its derived bound on random arms (and every value in its format)" in {
    val rng = new Random(Seeds("model-bound", 33L))
    (2 to 7).foreach { n =>
      val chain = RandomChains.chain(rng, n)
      val vmax = Seq.fill(n)(1 + 3 * rng.nextDouble())
      val amax = Seq.fill(n)(5 + 10 * rng.nextDouble())
      val p = randomArm(chain, vmax, amax)
      val model = new ArmModel(p)
      val worst = (0 until 40).map { _ =>
        val (q, qd, qdd) = RandomChains.sample(rng, vmax, amax)
        val hw = model.evaluate(ArmSample(q, qd, qdd))
        val ref = Rnea.reference(chain, q, qd, qdd)
        hw.indices.map { j =>
          val err = math.abs(hw(j) - ref(j))
          assert(
            err <= p.errorBounds(j),
            s"$n joints, joint ${j + 1}: error $err above the bound ${p.errorBounds(j)}"
          )
          err / p.errorBounds(j)
        }.max
      }.max
      println(
        f"[dynamics] random $n-joint arm: ${p.graph.counts.multiplications} multiplications, worst error at ${worst * 100}%.1f%% of the bound (max bound ${p.errorBound}%.2e N·m)"
      )
    }
  }
}
