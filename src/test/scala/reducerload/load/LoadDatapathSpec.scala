package reducerload.load

import reducerload.testutil.CompiledParams
import reducerload.config.LoadParams
import reducerload.arm.LoadReference
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.arm.ArmChecks
import reducerload.testutil.{Golden, GoldenTrace, Seeds, SimBackend}

import scala.util.Random

/**
 * The joint-3 closed forms on the arm datapath, one simulation per design: every golden trace back to back,
 * then seeded random samples (one in eight beyond the declared ranges) with bubbles and resets, each offered
 * until taken. Checked ([[ArmChecks.run]]): bit-exact against the model at exactly the reported latency,
 * samples entering every clocks-per-sample clocks, and the load within the derived bound and the target of
 * the double-precision closed form and of the independent golden loads (Pinocchio's RNEA, the golden script's
 * closed forms).
 */
class LoadDatapathSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "the joint-3 load datapath"

  private def runDesign(label: String, p: LoadParams, target: Double, seed: Long): Unit = {
    val traces = Golden.all
    traces.foreach(t =>
      assert(t.robot == p.robot, s"golden trace ${t.name} is for another robot: ${t.robot}")
    )
    assert(p.errorBound <= target, s"$label: derived bound ${p.errorBound} misses the target $target")
    val rng = new Random(Seeds(label, seed))
    val random = IndexedSeq.fill(SimBackend.scale(4000)) {
      if (rng.nextInt(8) == 0) LoadChecks.outOfRangeSample(p.robot, rng)
      else LoadChecks.randomSample(p.robot, rng)
    }
    def golden(pick: GoldenTrace => IndexedSeq[Double]) = traces.flatMap(pick).map(IndexedSeq(_)).toIndexedSeq
    val goldenTorques =
      if (p.model == LoadModel.Exact) Seq("pinocchio" -> golden(_.rnea), "golden exact" -> golden(_.exact))
      else Seq("golden paper" -> golden(_.paper))
    ArmChecks.run(
      this,
      label,
      p.arm,
      traces.flatMap(_.samples).toIndexedSeq,
      random,
      rng,
      goldenTorques,
      target,
      s => IndexedSeq(LoadReference.torque(p.robot, p.model, s))
    )
  }

  it should "compute the exact load within 1e-4 N·m on every golden trace (default preset)" in {
    runDesign("default", LoadParams.default, 1e-4, 21L)
  }

  it should "reproduce the paper's equation (6) within 1e-3 N·m on every golden trace (paper preset)" in {
    runDesign("paper", LoadParams.paper, 1e-3, 22L)
  }

  it should "compute the exact load within 1e-3 N·m with one CORDIC unit shared by the three angles, a sample every 3 clocks (compact preset)" in {
    assert(
      LoadParams.compact.arm.schedule.cordicUnits == 1 && LoadParams.compact.arm.schedule.clocksPerSample == 3
    )
    runDesign("compact", LoadParams.compact, 1e-3, 23L)
  }

  it should "compute the exact load within 1e-4 N·m with one CORDIC unit and shared multipliers, fraction bits from the target (shared preset)" in {
    runDesign("shared", LoadParams.shared, 1e-4, 24L)
  }

  it should "compute the same loads with its constant multiplies as shift-and-add logic, one sample per clock and shared (schedule.constant-multiplies)" in {
    import reducerload.graph.ConstantMultiplies
    Seq(
      ("default-shift-add", LoadParams.default, 1e-4, 25L),
      ("compact-shift-add", LoadParams.compact, 1e-3, 26L)
    ).foreach { case (label, preset, target, seed) =>
      val p = preset.copy(schedule = preset.schedule.copy(constantMultiplies = ConstantMultiplies.ShiftAdd))
      val (blocks, shiftAdd) = (preset.arm.schedule, p.arm.schedule)
      assert(
        shiftAdd.shiftAdded.size == p.arm.graph.counts.constantMultiplications && shiftAdd.multiplierBlocks < blocks.multiplierBlocks,
        s"$label: ${shiftAdd.multiplierBlocks} blocks with ${shiftAdd.shiftAdded.size} shift-add multiplies, ${blocks.multiplierBlocks} without"
      )
      runDesign(label, p, target, seed)
    }
  }
}
