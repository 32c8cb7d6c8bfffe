package reducerload.arm

import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.dynamics.{RandomChains, Rnea}
import reducerload.graph.SampleCodes
import reducerload.load.RobotParams
import reducerload.robot.Planar3
import reducerload.sim.{ArmDriver, Cycle, Stream}
import reducerload.testutil.{Golden, Seeds, SimBackend}

import scala.collection.mutable.ArrayBuffer
import scala.util.Random

/**
 * One simulation per design: golden samples back to back (one per clock), then seeded random
 * samples (some beyond the declared ranges) with bubbles and resets. Checked: bit-exact against the
 * model at exactly the reported latency, and every in-range torque within the derived bound of
 * double-precision RNEA and of the independent golden torques.
 */
class ArmDatapathSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "ArmDatapath"

  it should "compute all three torques of the planar arm, bit-exact with the model, within its bound of Pinocchio's tau3" in {
    val robot = RobotParams()
    val p = ArmParams(Planar3.chain(robot), robot.maxVelocity, robot.maxAcceleration)
    val traces = Golden.all
    val golden = traces.flatMap(_.samples.map(s => ArmSample(IndexedSeq(s.t1, s.t2, s.t3), IndexedSeq(s.d1, s.d2, s.d3), IndexedSeq(s.dd1, s.dd2, s.dd3))))
    val pinocchioTau3 = traces.flatMap(_.rnea).toIndexedSeq
    val rng = new Random(Seeds("arm-planar3", 41L))
    val random = IndexedSeq.fill(SimBackend.scale(2000)) {
      val (q, qd, qdd) = RandomChains.sample(rng, robot.maxVelocity.map(_ * 1.1), robot.maxAcceleration.map(_ * 1.1))
      ArmSample(q, qd, qdd)
    }
    ArmChecks.run(this, "planar3", p, golden.toIndexedSeq, Some(sample => pinocchioTau3), random, rng)
  }
}

/** Test logic, apart from the simulator calls (those are in ArmDriver). */
object ArmChecks {

  /** Runs golden samples then random ones through the RTL; checks bits against the model and torques against references. */
  def run(
    spec: AnyFlatSpec with ChiselScalatestTester,
    label: String,
    p: ArmParams,
    golden: IndexedSeq[ArmSample],
    goldenLastJoint: Option[Int => IndexedSeq[Double]],
    random: IndexedSeq[ArmSample],
    rng: Random,
    goldenTorques: Option[IndexedSeq[IndexedSeq[Double]]] = None
  ): Unit = {
    import spec._
    val model = new ArmModel(p)
    val latency = p.latency
    val goldenCodes = golden.map(model.encode)
    val stim = (goldenCodes.map(Cycle.Sample(_)) ++ Stream.randomStimulus(rng, random.map(model.encode), bubble = 0.2, resets = 2)) ++
      IndexedSeq.fill(latency + 1)(Cycle.Bubble)
    test(new ArmDatapath(p)).withAnnotations(SimBackend.annotations) { dut =>
      val observed = ArrayBuffer.empty[Option[ArmOutputCodes]]
      ArmDriver.run(dut, stim.iterator, (_, out) => observed += out)
      val expected = Stream.expected[SampleCodes](stim, latency).map(_.map(model.evaluate))
      val bad = Stream.mismatches[ArmOutputCodes, ArmOutputCodes](expected, observed.toIndexedSeq, _ == _)
      assert(bad.isEmpty, bad.mkString(s"$label: RTL differs from the model:\n", "\n", ""))
      val hw = golden.indices.map(k => observed(latency + k).getOrElse(fail(s"$label: golden sample $k produced no output")))
      assert(hw.forall(!_.outOfRange.exists(identity)), s"$label: an in-range golden sample raised outOfRange")
      val tau = hw.map(model.torques)
      val ref = golden.map(s => Rnea.reference(p.chain, s.q, s.qd, s.qdd))
      p.jointNames.indices.foreach { j =>
        val err = tau.zip(ref).map { case (h, r) => math.abs(h(j) - r(j)) }.max
        println(f"[arm] $label ${p.jointNames(j)}%-22s max |hw - rnea| $err%.3e N·m (bound ${p.errorBounds(j)}%.3e)")
        assert(err <= p.errorBounds(j), s"$label joint ${j + 1}: error $err above the derived bound ${p.errorBounds(j)}")
      }
      goldenTorques.foreach { g =>
        p.jointNames.indices.foreach { j =>
          val err = tau.zip(g).map { case (h, r) => math.abs(h(j) - r(j)) }.max
          println(f"[arm] $label ${p.jointNames(j)}%-22s max |hw - pinocchio| $err%.3e N·m (bound ${p.errorBounds(j)}%.3e, target 1e-3)")
          assert(err <= p.errorBounds(j) + 1e-9 && err <= 1e-3, s"$label joint ${j + 1}: error vs Pinocchio $err")
        }
      }
      goldenLastJoint.foreach { f =>
        val pin = f(0)
        val j = p.chain.size - 1
        val err = tau.zip(pin).map { case (h, r) => math.abs(h(j) - r) }.max
        println(f"[arm] $label ${p.jointNames(j)} max |hw - pinocchio tau3| $err%.3e N·m (bound ${p.errorBounds(j)}%.3e)")
        assert(err <= p.errorBounds(j) + 1e-9 && err <= 1e-4)
      }
      println(s"[arm] $label: latency $latency cycles, ${p.graph.counts}, outputs bit-exact with the model over ${stim.size} cycles")
    }
  }
}
