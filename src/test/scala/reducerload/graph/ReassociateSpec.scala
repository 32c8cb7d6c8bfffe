package reducerload.graph

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.arm.{ArmModel, ArmParams, ArmSample}
import reducerload.compiler.Compiler
import reducerload.dynamics.{RandomChains, Rnea}
import reducerload.testutil.{ArmGolden, Seeds}

import scala.util.Random

/**
 * `datapath.reassociate = sums`: the rebuilt graph computes what the written one does (doubles, on seeded
 * random inputs), keeps its products and sharing, has a shorter critical path, and its bit-accurate model
 * stays within its own derived bounds of double-precision RNEA.
 */
class ReassociateSpec extends AnyFlatSpec {
  behavior of "Reassociate"

  private def pair(robot: String): (ArmParams, ArmParams) = {
    val arm = Compiler.arm(ArmGolden.of(robot).head.config)
    def as(r: Reassociation) = arm.copy(datapath = arm.datapath.copy(reassociate = r))
    (as(Reassociation.Off), as(Reassociation.Sums))
  }

  // planar3's sums are of two or three terms that arrive together: nothing to gain, nothing lost.
  for ((robot, seed, shorter) <- Seq(("planar3", 61L, false), ("ur5", 62L, true), ("panda", 63L, true)))
    it should s"compute the written graph's torques of $robot with a critical path no longer" in {
      val (written, rebuilt) = pair(robot)
      val (g0, g1) = (written.graph, rebuilt.graph)
      val delays = written.arrivalDelays
      val (d0, d1) = (Reassociate.depth(g0, delays), Reassociate.depth(g1, delays))
      info(
        s"$robot: critical path $d0 -> $d1 clocks (add ${delays.add}, mul ${delays.mul}, trig ${delays.trig}); " +
          s"${g0.counts} -> ${g1.counts}"
      )
      assert(if (shorter) d1 < d0 else d1 <= d0, s"$robot: critical path $d0 -> $d1")
      assert(g1.counts.multiplications == g0.counts.multiplications)
      assert(g1.counts.sinCos == g0.counts.sinCos)
      assert(
        g1.counts.additions + g1.counts.negations <= g0.counts.additions + g0.counts.negations,
        s"$robot: ${g0.counts} -> ${g1.counts}"
      )
      assert(g1.outputs.map(_.name) == g0.outputs.map(_.name))

      val rng = new Random(Seeds(s"reassociate-$robot", seed))
      val model = new ArmModel(rebuilt)
      (0 until 200).foreach { k =>
        val (q, qd, qdd) = RandomChains.sample(rng, written.maxVelocity, written.maxAcceleration)
        val (t0, t1) = (GraphReference.outputs(g0, q, qd, qdd), GraphReference.outputs(g1, q, qd, qdd))
        t0.zip(t1).zipWithIndex.foreach { case ((a, b), j) =>
          assert(
            math.abs(a - b) <= 1e-9 * math.max(1.0, math.abs(a)),
            s"$robot sample $k joint ${j + 1}: $a vs $b"
          )
        }
        // The rebuilt graph's own analysis bounds its fixed-point torques (the model checks every format).
        val exact = Rnea.reference(rebuilt.chain, q, qd, qdd)
        val got = model.torques(model.evaluate(model.encode(ArmSample(q, qd, qdd))))
        got.zip(exact).zip(rebuilt.errorBounds).zipWithIndex.foreach { case (((g, e), bound), j) =>
          assert(math.abs(g - e) <= bound, s"$robot sample $k joint ${j + 1}: |$g - $e| > $bound")
        }
      }
    }

  it should "leave the written graph as it is when off" in {
    val (written, _) = pair("ur5")
    val again = ArmParams.rneaGraph(written.chain, written.maxVelocity, written.maxAcceleration)._1
    assert(written.graph == again)
  }
}
