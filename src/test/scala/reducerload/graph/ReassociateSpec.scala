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
 * stays within its own derived bounds of double-precision RNEA. `sums-and-products` the same, with a shorter
 * critical path than `sums` for a few more products, and rotations by scaled factors that the analysis
 * bounds.
 */
class ReassociateSpec extends AnyFlatSpec {
  behavior of "Reassociate"

  private def as(robot: String, r: Reassociation): ArmParams = {
    val arm = Compiler.arm(ArmGolden.of(robot).head.config)
    arm.copy(datapath = arm.datapath.copy(reassociate = r))
  }
  private def pair(robot: String): (ArmParams, ArmParams) =
    (as(robot, Reassociation.Off), as(robot, Reassociation.Sums))

  /**
   * `rebuilt` computes `written`'s torques in doubles on seeded random inputs, and its bit-accurate model
   * stays within its own derived bounds of double-precision RNEA (the model checks every node's format).
   */
  private def sameTorques(robot: String, seed: Long, written: ArmParams, rebuilt: ArmParams): Unit = {
    val rng = new Random(Seeds(s"reassociate-${rebuilt.datapath.reassociate}-$robot", seed))
    val model = new ArmModel(rebuilt)
    (0 until 200).foreach { k =>
      val (q, qd, qdd) = RandomChains.sample(rng, written.maxVelocity, written.maxAcceleration)
      val (t0, t1) =
        (GraphReference.outputs(written.graph, q, qd, qdd), GraphReference.outputs(rebuilt.graph, q, qd, qdd))
      t0.zip(t1).zipWithIndex.foreach { case ((a, b), j) =>
        assert(
          math.abs(a - b) <= 1e-9 * math.max(1.0, math.abs(a)),
          s"$robot sample $k joint ${j + 1}: $a vs $b"
        )
      }
      val exact = Rnea.reference(rebuilt.chain, q, qd, qdd)
      val got = model.torques(model.evaluate(model.encode(ArmSample(q, qd, qdd))))
      got.zip(exact).zip(rebuilt.errorBounds).zipWithIndex.foreach { case (((g, e), bound), j) =>
        assert(math.abs(g - e) <= bound, s"$robot sample $k joint ${j + 1}: |$g - $e| > $bound")
      }
    }
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

      sameTorques(robot, seed, written, rebuilt)
    }

  for ((robot, seed) <- Seq(("planar3", 64L), ("ur5", 65L), ("panda", 66L)))
    it should s"compute the written graph's torques of $robot with products reassociated, on a shorter path" in {
      val (written, sums) = pair(robot)
      val rebuilt = as(robot, Reassociation.SumsAndProducts)
      val (g1, g2) = (sums.graph, rebuilt.graph)
      val delays = written.arrivalDelays
      val (d1, d2) = (Reassociate.depth(g1, delays), Reassociate.depth(g2, delays))
      val scaled = g2.ids.count(id =>
        Rotation.isRotation(g2, id) && g2(id).operands.exists(m =>
          Rotation.term(g2, m).exists(_.scale.isDefined)
        )
      )
      info(
        s"$robot: critical path $d1 -> $d2 clocks; ${g1.counts} -> ${g2.counts}; $scaled rotations by k sin/cos"
      )
      assert(d2 < d1, s"$robot: critical path $d1 -> $d2")
      assert(scaled > 0, s"$robot: no rotation by a scaled factor to bound")
      assert(g2.counts.sinCos == g1.counts.sinCos)
      // Each distributed product term costs a product (planar3 +3 of 31, the UR5 +12 of 249).
      assert(
        g2.counts.multiplications <= g1.counts.multiplications * 110 / 100,
        s"$robot: ${g1.counts} -> ${g2.counts}"
      )
      sameTorques(robot, seed, written, rebuilt)
    }

  it should "leave the written graph as it is when off" in {
    val (written, _) = pair("ur5")
    val again = ArmParams.rneaGraph(written.chain, written.maxVelocity, written.maxAcceleration)._1
    assert(written.graph == again)
  }
}
