package reducerload.config

import com.typesafe.config.ConfigFactory
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.app.Main
import reducerload.cordic.CordicParams
import reducerload.load.LoadModel
import reducerload.robot.RobotParams
import reducerload.util.InputError

import java.nio.file.{Files, Paths}

class SettingsSpec extends AnyFlatSpec {
  behavior of "Settings"

  private def parse(text: String, source: String = "test.conf") =
    Settings.toParams(ConfigFactory.parseString(text), source)
  private val defaultText = Settings.render(LoadParams.default, Nil)

  it should "ship preset files that are exactly the presets in the code" in {
    LoadParams.allPresets.foreach { case (name, p) =>
      val file = Paths.get("configs", s"$name.conf")
      val text = new String(Files.readAllBytes(file), "UTF-8")
      assert(
        text == Settings.render(p, Main.presetHeader(name)),
        s"$file is stale: regenerate it as its header says"
      )
      assert(parse(text, file.toString) == p)
    }
  }

  it should "round-trip parameters through a configuration file" in {
    val p = LoadParams(
      robot = RobotParams(
        m3 = 7.5,
        l1 = 0.5,
        l2 = 0.25,
        l3 = 0.45,
        g = 0.0,
        maxVelocity = Seq(1.0, 2.0, 3.5),
        maxAcceleration = Seq(4.0, 5.0, 6.0)
      ),
      model = LoadModel.PaperEq6,
      cordic = CordicParams(
        angleBits = 20,
        outputBits = 18,
        iterations = 15,
        guardBits = 3,
        angleGuardBits = 4,
        iterationsPerStage = 2
      ),
      datapath = DatapathParams(
        velocityFracBits = 14,
        accelerationFracBits = 15,
        constantFracBits = 18,
        internalFracBits = 16,
        outputFracBits = 12,
        multiplierLatency = 2
      )
    )
    assert(parse(Settings.render(p, Seq("x"))) == p)
  }

  it should "name the key and the file for unknown keys, wrong types, missing keys and bad values" in {
    def refused(text: String, words: String*): Unit = {
      val e = intercept[InputError](parse(text))
      assert(!e.getMessage.contains("\n"), s"error spans lines: ${e.getMessage}")
      (words :+ "test.conf").foreach(w =>
        assert(e.getMessage.contains(w), s"'${e.getMessage}' does not mention '$w'")
      )
    }
    refused(defaultText + "\nrobot.mass = 3\n", "unknown key 'robot.mass'")
    refused(
      defaultText + "\ncordic.iteration = 3\n",
      "unknown key 'cordic.iteration'",
      "did you mean 'cordic.iterations'"
    )
    refused(defaultText + "\nrobot.m3 = heavy\n", "robot.m3", "a number")
    refused(defaultText + "\ncordic.iterations = 12.5\n", "cordic.iterations", "an integer")
    refused(defaultText + "\nmodel = newton\n", "model", "exact, paper")
    refused(defaultText + "\nrobot.max-velocity = [1, 2]\n", "robot.max-velocity", "3 numbers")
    refused(defaultText.linesIterator.filterNot(_.contains("m3 =")).mkString("\n"), "missing key 'robot.m3'")
    refused(defaultText + "\nrobot.m3 = -1\n", "m3", "must be")
    refused(defaultText + "\ncordic.iterations = 0\n", "iterations")
    refused(defaultText + "\nrobot.units = imperial\n", "unknown key 'robot.units'")
  }
}
