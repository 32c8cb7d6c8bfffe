package reducerload.config

import org.scalatest.flatspec.AnyFlatSpec
import org.scalatest.matchers.should.Matchers
import reducerload.app.{Cli, Emit}
import reducerload.util.InputError

class DeviceSpec extends AnyFlatSpec with Matchers {
  private def params(args: String*) = Cli.parse("emit", args, Emit.options).params

  "device" should "default to the EP4CE30 and take every Cyclone IV E size and the ECP5 parts" in {
    LoadParams.default.device.part shouldBe Device.EP4CE30
    Device.all.map(_.name) should contain allOf (
      "EP4CE6",
      "EP4CE10",
      "EP4CE15",
      "EP4CE22",
      "EP4CE30",
      "EP4CE40",
      "EP4CE55",
      "EP4CE75",
      "EP4CE115",
      "LFE5U-45F"
    )
    params("--device", "EP4CE115").device.part.logicElements shouldBe 114480
    params("--device", "LFE5U-45F").device.part.family shouldBe DeviceFamily.ECP5
  }

  it should "refuse an unknown device in one line naming the known ones" in {
    val e = intercept[InputError](params("--device", "EP4CE99"))
    e.getMessage.linesIterator.size shouldBe 1
    e.getMessage should include("EP4CE99")
    e.getMessage should include("EP4CE30")
    e.getMessage should include("LFE5U-85F")
  }

  it should "refuse a logic fraction outside (0, 1]" in {
    val e = intercept[InputError](params("--device.max-logic-fraction", "1.5"))
    e.getMessage should include("device.max-logic-fraction must be in (0, 1]")
  }

  "a memory block count" should "take the fewest blocks of one shape" in {
    DeviceFamily.CycloneIVE.blocksFor(512, 62) shouldBe 4 // 512x18
    DeviceFamily.CycloneIVE.blocksFor(7, 64) shouldBe 2 // 256x36
    DeviceFamily.CycloneIVE.blocksFor(8192, 1) shouldBe 1
    DeviceFamily.ECP5.blocksFor(512, 62) shouldBe 2 // 512x36
  }
}
