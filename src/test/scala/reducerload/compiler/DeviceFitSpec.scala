package reducerload.compiler

import org.scalatest.flatspec.AnyFlatSpec
import org.scalatest.matchers.should.Matchers
import reducerload.app.{Cli, Emit}
import reducerload.config.Device
import reducerload.graph.Storage
import reducerload.util.InputError

/** The device fit: scheduling only (no elaboration), on the golden UR5 and Panda. */
class DeviceFitSpec extends AnyFlatSpec with Matchers {
  private val ur5 =
    Seq("--robot", "golden/robots/ur5_robot.urdf", "--tip", "tool0", "--max-acceleration", "15")
  private def params(args: Seq[String]) = Cli.parse("emit", args, Emit.options).params
  private def compiled(args: Seq[String]) = Compiler.compile(params(args), "command line")

  private def timed[T](what: String)(body: => T): T = {
    val start = System.nanoTime()
    val result = body
    println(f"$what: ${(System.nanoTime() - start) / 1e9}%.2f s")
    result
  }

  "emit --robot with no schedule settings" should "choose the fastest UR5 design that fits an EP4CE30" in {
    val c = timed("UR5 device fit (compile)")(compiled(ur5))
    val d = Device.EP4CE30
    val r = c.fit.design.resources
    println(c.fit.line)
    c.fit.chosen shouldBe true
    c.warnings shouldBe empty
    r.multiplierBlocks should be <= d.multiplierBlocks
    r.memoryBlocks should be <= d.memoryBlocks
    r.logicElements should be <= (d.logicElements * 0.8).toInt
    c.arm.schedule.multiplierBlocks shouldBe r.multiplierBlocks
    c.fit.line should startWith(s"device EP4CE30: chose ${c.arm.schedule.clocksPerSample} clocks per sample")
    // The fastest: one clock fewer does not fit, with or without block-RAM delays, nor refined again.
    val faster = c.arm.schedule.clocksPerSample - 1
    val steps = reducerload.graph.ScheduleRequest.defaultRefinement
    Seq("4" -> steps, "4" -> steps * DeviceFit.closeRefinementFactor, "0" -> steps).foreach {
      case (delays, n) =>
        val tighter = Compiler.arm(
          params(
            ur5 ++ Seq(
              "--clocks-per-sample",
              faster.toString,
              "--schedule.storage",
              "registers",
              "--datapath.memory-delay-min-cycles",
              delays,
              "--schedule.refinement",
              n.toString
            )
          )
        )
        val fr = ResourceModel.of(tighter, d.family)
        withClue(s"$faster clocks per sample, memory-delay-min-cycles $delays, refinement $n: ") {
          (fr.multiplierBlocks > d.multiplierBlocks || fr.memoryBlocks > d.memoryBlocks ||
            fr.logicElements > (d.logicElements * 0.8).toInt) shouldBe true
        }
    }
  }

  it should "fit the Panda within a minute" in {
    val golden = reducerload.arm.ArmGolden.of("panda").head.config
    val c = timed("Panda device fit (compile)")(Compiler.compile(golden, "panda"))
    println(c.fit.line)
    c.fit.chosen shouldBe true
    c.fit.design.resources.multiplierBlocks should be <= Device.EP4CE30.multiplierBlocks
  }

  it should "refuse, with the numbers, a robot that fits the device at no clocks per sample" in {
    val e = intercept[InputError](compiled(ur5 ++ Seq("--device", "EP4CE6")))
    println(e.getMessage)
    e.getMessage should include("no design fits the device EP4CE6")
    e.getMessage should include("/6,272 LEs")
    e.getMessage.linesIterator.size shouldBe 1
  }

  "an explicit schedule" should "be built as asked, with a warning naming the multiplier blocks it takes beyond the device" in {
    val c = compiled(ur5 ++ Seq("--clocks-per-sample", "1"))
    c.arm.schedule.clocksPerSample shouldBe 1
    c.fit.chosen shouldBe false
    val blocks = c.arm.schedule.multiplierBlocks
    blocks should be > 66
    c.warnings.map(_.toString) should contain(
      s"warning: device EP4CE30: the design (1 clock per sample, registers storage) uses $blocks 18x18 multiplier blocks, the device has 66"
    )
  }

  "schedule.max-multipliers alone" should "choose the clocks per sample that fit instead of being refused" in {
    // a tenth of the default refinement: the search is the same, each candidate's annealing shorter
    val steps = reducerload.graph.ScheduleRequest.defaultRefinement / 10
    val c = compiled(ur5 ++ Seq("--schedule.max-multipliers", "66", "--schedule.refinement", steps.toString))
    c.arm.schedule.multiplierBlocks should be <= 66
    c.arm.schedule.clocksPerSample should be > 1
    c.warnings shouldBe empty
  }

  "a preset that fits at one clock per sample" should "keep its schedule" in {
    val c = compiled(Nil)
    c.arm.schedule.clocksPerSample shouldBe 1
    c.arm.scheduleRequest.stored shouldBe Storage.Registers
    c.fit.line should startWith("device EP4CE30: chose 1 clock per sample, registers storage")
  }
}
