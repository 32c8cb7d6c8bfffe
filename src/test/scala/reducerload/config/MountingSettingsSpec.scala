package reducerload.config

import com.typesafe.config.ConfigFactory
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.app.Main
import reducerload.load.LoadModel
import reducerload.robot.{Mounting, RobotParams, Vec3}
import reducerload.util.InputError

import java.io.{ByteArrayOutputStream, PrintStream}

class MountingSettingsSpec extends AnyFlatSpec {
  behavior of "robot.base-rpy"

  private val defaultText = Settings.render(LoadParams.default, Nil)
  private def parse(extra: String) =
    Settings.toParams(ConfigFactory.parseString(defaultText + "\n" + extra + "\n"), "test.conf")
  private val ur5 = RobotParams(source = "golden/robots/ur5_robot.urdf", tip = "tool0", maxVelocity = Nil)
    .copy(maxAcceleration = Seq(15.0))

  it should "read named mountings and roll, pitch, yaw, and write them back" in {
    assert(LoadParams.default.robot.mounting == Mounting.floor)
    assert(parse("model = rnea\nrobot.base-rpy = ceiling").robot.mounting == Mounting.ceiling)
    assert(parse("model = rnea\nrobot.base-rpy = wall").robot.mounting == Mounting(0, math.Pi / 2, 0))
    assert(parse("model = rnea\nrobot.base-rpy = [0.1, -0.2, 3]").robot.mounting == Mounting(0.1, -0.2, 3))
    assert(parse("robot.base-rpy = [0, 0, 0]").robot.mounting == Mounting.floor)
    val p = LoadParams.arm.copy(robot = ur5.copy(mounting = Mounting(0.25, 0.5, -1.0)))
    assert(Settings.toParams(ConfigFactory.parseString(Settings.render(p, Nil)), "x") == p)
    assert(Settings.robotBaseRpy.render(LoadParams.default) == "floor")
  }

  it should "refuse bad values with one line naming the key and the file" in {
    def refused(extra: String, words: String*): Unit = {
      val e = intercept[InputError](parse(extra))
      assert(!e.getMessage.contains("\n"))
      (words :+ "test.conf").foreach(w => assert(e.getMessage.contains(w), s"'${e.getMessage}' lacks '$w'"))
    }
    refused("robot.base-rpy = roof", "robot.base-rpy", "floor, ceiling, wall or [roll, pitch, yaw]", "'roof'")
    refused("robot.base-rpy = [1, 2]", "robot.base-rpy", "three numbers")
    refused("robot.base-rpy = [1, 2, x]", "robot.base-rpy", "three numbers")
    refused("robot.base-rpy = 3", "robot.base-rpy")
    refused("robot.base-rpy = [0, 7, 0]", "robot.base-rpy", "pitch", "[-2 pi, 2 pi]")
    // planar3's joint-3 closed form has the floor's gravity built in.
    refused("robot.base-rpy = ceiling", "robot.base-rpy", "model rnea")
  }

  it should "take the mounting from the command line, as a name or as roll,pitch,yaw" in {
    def run(args: String*) = {
      val out = new ByteArrayOutputStream()
      val err = new ByteArrayOutputStream()
      val status = Console.withOut(new PrintStream(out))(Main.execute(args, new PrintStream(err)))
      (status, out.toString("UTF-8"), err.toString("UTF-8"))
    }
    val (ok, text, _) = run("config", "--model", "rnea", "--base-rpy", "0.5,0,0")
    assert(ok == 0 && text.contains("base-rpy = [0.5, 0.0, 0.0]"), text)
    val (named, text2, _) = run("config", "--model", "rnea", "--mounting", "wall")
    assert(named == 0 && text2.contains("base-rpy = wall"), text2)
    val (bad, _, err) = run("config", "--model", "rnea", "--base-rpy", "sideways")
    assert(bad == 2 && err.trim.linesIterator.size == 1 && err.contains("robot.base-rpy"), err)
  }

  it should "rotate a URDF robot's gravity (0, 0, -g) into the base frame, and planar3's own (+g, 0, 0)" in {
    assert(ur5.chain.gravity == Vec3(0, 0, -9.81))
    val floor = ur5.chain
    assert(floor.mounted(Mounting.floor) eq floor) // the default leaves every design as it was
    assert(Mounting(-0.0, 0, 0).isFloor)
    assert(ur5.copy(mounting = Mounting.ceiling).chain.gravity == Vec3(0, 0, 9.81))
    assert(ur5.copy(mounting = Mounting.wall).chain.gravity == Vec3(9.81, 0, 0))
    val tilt = ur5.copy(mounting = Mounting(0, math.Pi / 6, 0)).chain.gravity
    assert((tilt - Vec3(9.81 * 0.5, 0, -9.81 * math.sqrt(0.75))).norm < 1e-12)
    // planar3: the rotation applies to its own gravity; a yaw of pi/2 turns +x into base -y.
    val planar = RobotParams(mounting = Mounting(0, 0, math.Pi / 2)).chain.gravity
    assert(planar == Vec3(0, -9.81, 0))
    assert(RobotParams().chain.gravity == Vec3(9.81, 0, 0))
    assert(
      LoadParams(robot = RobotParams(mounting = Mounting.wall), model = LoadModel.Rnea).robot.chain.size == 3
    )
  }
}
