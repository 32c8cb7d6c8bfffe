package reducerload.app

import reducerload.testutil.CompiledParams
import reducerload.testutil.Scratch
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.compiler.Compiler
import reducerload.config.LoadParams
import reducerload.load.LoadModel
import reducerload.util.InputError

import java.nio.file.Files

class CliSpec extends AnyFlatSpec {
  behavior of "the command line"

  private def params(args: String*) = Cli.parse("emit", args, Emit.options).params

  /** Parsing checks the settings; compiling the design checks the rest (robot file, ranges, schedule). */
  private def compiled(args: String*) = Cli.parse("emit", args, Emit.options).compiled

  it should "start from the default preset and apply flag overrides" in {
    assert(params() == LoadParams.default)
    assert(params("--preset", "paper") == LoadParams.paper)
    val p = params("--m3", "12", "--model", "paper", "--max-velocity", "1,2,3", "--cordic.iterations=20")
    assert(
      p.robot.m3 == 12 && p.model == LoadModel.PaperEq6 && p.robot.maxVelocity == Seq(
        1.0,
        2.0,
        3.0
      ) && p.cordic.iterations == 20
    )
  }

  it should "refuse bad flags with one line naming the flag" in {
    def refused(args: Seq[String], word: String): Unit = {
      val e = intercept[InputError](compiled(args: _*))
      assert(e.getMessage.contains(word) && !e.getMessage.contains("\n"), e.getMessage)
    }
    refused(Seq("--frobnicate", "1"), "--frobnicate")
    refused(Seq("--m3"), "--m3 needs a value")
    refused(Seq("--m3", "heavy"), "robot.m3")
    refused(Seq("--m3", "NaN"), "robot.m3")
    refused(Seq("--preset", "fastest-ever"), "fastest-ever")
    refused(Seq("--preset", "paper", "--config", "x.conf"), "exclusive")
    refused(Seq("--config", "/nonexistent/x.conf"), "/nonexistent/x.conf")
    refused(Seq("--l2", "-0.3"), "l2")
  }

  it should "take a robot's every joint from --robot: the arm preset, model rnea, the URDF's velocity limits" in {
    val ur5 = params("--robot", "golden/robots/ur5_robot.urdf", "--tip", "tool0", "--max-acceleration", "15")
    assert(
      ur5.model == LoadModel.Rnea && ur5.cordic == LoadParams.arm.cordic && ur5.robot.maxVelocity.isEmpty
    )
    val arm = Compiler.arm(ur5)
    assert(
      arm.chain.size == 6 && arm.maxVelocity == Seq(3.15, 3.15, 3.15, 3.2, 3.2,
        3.2) && arm.maxAcceleration == Seq.fill(6)(15.0)
    )
    assert(params("--robot", "planar3") == LoadParams.arm)
    val hand = java.nio.file.Paths.get(getClass.getResource("/urdf/arm.urdf").toURI).toString
    assert(
      Compiler
        .arm(params("--robot", hand, "--tip", "l2", "--max-acceleration", "5", "--max-velocity", "2"))
        .chain
        .size == 2
    )
  }

  it should "refuse a robot's bad ranges, tip or file with one line naming it" in {
    def refused(args: Seq[String], words: String*): Unit = {
      val e = intercept[InputError](compiled(args: _*))
      assert(words.forall(e.getMessage.contains) && !e.getMessage.contains("\n"), e.getMessage)
    }
    val ur5 = Seq("--robot", "golden/robots/ur5_robot.urdf", "--tip", "tool0")
    refused(ur5, "--max-acceleration")
    refused(ur5 ++ Seq("--max-acceleration", "[1, 2, 3, 4]"), "6 joints", "max-acceleration", "4 values")
    refused(ur5 ++ Seq("--max-acceleration", "15", "--max-velocity", "[1, 2]"), "max-velocity", "2 values")
    refused(Seq("--robot", "golden/robots/ur5_robot.urdf", "--max-acceleration", "15"), "--tip", "tool0")
    refused(
      Seq("--robot", "golden/robots/ur5_robot.urdf", "--tip", "nowhere", "--max-acceleration", "15"),
      "nowhere"
    )
    refused(Seq("--robot", "/nonexistent/arm.urdf", "--max-acceleration", "15"), "/nonexistent/arm.urdf")
    refused(ur5 ++ Seq("--max-acceleration", "15", "--model", "exact"), "model exact", "rnea")
    refused(Seq("--robot", "planar3", "--datapath.cordic-units", "1"), "cordic-units")
    refused(
      ur5 ++ Seq("--max-acceleration", "15", "--max-multipliers", "5", "--clocks-per-sample", "auto"),
      "schedule.max-multipliers = 5",
      "use at least"
    )
    refused(
      ur5 ++ Seq("--max-acceleration", "15", "--max-multipliers", "66", "--clocks-per-sample", "4"),
      "schedule.max-multipliers = 66",
      "clocks-per-sample >= 18"
    )
    refused(
      ur5 ++ Seq("--max-acceleration", "15", "--schedule.cordic-units", "2", "--clocks-per-sample", "1"),
      "schedule.cordic-units = 2",
      "5 sin/cos"
    )
    refused(ur5 ++ Seq("--max-acceleration", "15", "--clocks-per-sample", "0"), "schedule.clocks-per-sample")
    refused(
      ur5 ++ Seq("--max-acceleration", "15", "--clocks-per-sample", "fast"),
      "schedule.clocks-per-sample",
      "auto"
    )
    // The joint-3 closed form is a graph like any other: scheduled, not refused.
    assert(params("--clocks-per-sample", "4").arm.schedule.clocksPerSample == 4)
    refused(
      Seq("--robot", "planar3", "--schedule.storage", "memory", "--clocks-per-sample", "1"),
      "schedule.storage = memory",
      "clocks-per-sample >= 2"
    )
    refused(
      Seq("--robot", "planar3", "--clocks-per-sample", "4", "--schedule.storage", "memory"),
      "schedule.storage = memory",
      "clocks-per-sample >= 6"
    )
    refused(
      Seq("--robot", "planar3", "--clocks-per-sample", "8", "--schedule.storage", "disk"),
      "schedule.storage",
      "registers",
      "memory"
    )
    refused(
      Seq("--robot", "planar3", "--clocks-per-sample", "8", "--schedule.list-order", "by-cycle"),
      "schedule.list-order = by-cycle",
      "schedule.storage = memory"
    )
    refused(
      Seq(
        "--robot",
        "planar3",
        "--clocks-per-sample",
        "8",
        "--schedule.storage",
        "memory",
        "--schedule.list-order",
        "random"
      ),
      "schedule.list-order",
      "auto",
      "by-height",
      "by-cycle"
    )
    val hand = java.nio.file.Paths.get(getClass.getResource("/urdf/arm.urdf").toURI).toString
    refused(
      Seq("--robot", hand, "--tip", "l3", "--max-acceleration", "5", "--max-velocity", "2"),
      "wrist_slide",
      "prismatic"
    )
  }

  it should "derive the clocks per sample from a multiplier budget" in {
    val ur5 = Compiler.arm(
      params(
        "--robot",
        "golden/robots/ur5_robot.urdf",
        "--tip",
        "tool0",
        "--max-acceleration",
        "15",
        "--max-multipliers",
        "66",
        "--clocks-per-sample",
        "auto"
      )
    )
    assert(
      ur5.schedule.clocksPerSample == 18 && ur5.schedule.multiplierBlocks <= 66,
      s"${ur5.schedule.clocksPerSample} clocks, ${ur5.schedule.multiplierBlocks} blocks"
    )
    // With block-RAM storage, the fewest clocks from the budget's on whose bank read ports can be served.
    val banked = Compiler.arm(
      params(
        "--robot",
        "golden/robots/ur5_robot.urdf",
        "--tip",
        "tool0",
        "--max-acceleration",
        "15",
        "--max-multipliers",
        "66",
        "--clocks-per-sample",
        "auto",
        "--schedule.storage",
        "memory"
      )
    )
    val fewer = scala.util.Try(
      compiled(
        "--robot",
        "golden/robots/ur5_robot.urdf",
        "--tip",
        "tool0",
        "--max-acceleration",
        "15",
        "--max-multipliers",
        "66",
        "--clocks-per-sample",
        (banked.schedule.clocksPerSample - 1).toString,
        "--schedule.storage",
        "memory"
      )
    )
    assert(
      banked.banked.isDefined && banked.schedule.multiplierBlocks <= 66 && fewer.isFailure,
      s"memory: ${banked.schedule.clocksPerSample} clocks, ${banked.schedule.multiplierBlocks} blocks; one clock fewer ${if (fewer.isFailure) "refused" else "accepted"}"
    )
  }

  it should "name the file when a configuration file is not HOCON" in {
    val f = Scratch.file("bad", ".conf")
    Files.write(f, Array[Byte](0, 1, 2, '{'.toByte, '{'.toByte))
    val e = intercept[InputError](params("--config", f.toString))
    assert(e.getMessage.contains(f.toString), e.getMessage)
    Files.delete(f)
  }

  it should "document every setting with its unit and default in --help" in {
    val h = Main.help
    reducerload.config.Settings.all.foreach { s =>
      assert(h.contains("--" + s.key), s"--help lacks ${s.key}")
      assert(h.contains(s"(default ${s.render(LoadParams.default)}"))
    }
    Seq("--robot", "--tip", "rnea", "arm").foreach(w => assert(h.contains(w), s"--help lacks $w"))
  }

  it should "say in --help where a URDF robot's defaults come from, not show planar3's as theirs" in {
    val velocity = Main.help.linesIterator.find(_.contains("--robot.max-velocity")).get
    assert(velocity.contains("(default [3.0, 3.0, 3.0]; with --robot FILE: urdf)"), velocity)
    val acceleration = Main.help.linesIterator.find(_.contains("--robot.max-acceleration")).get
    assert(acceleration.contains("with --robot FILE: required"), acceleration)
    val model = Main.help.linesIterator.find(_.startsWith("  --model")).get
    assert(model.contains("with --robot FILE: rnea"), model)
  }

  it should "resolve relative paths against the caller's directory (REDUCERLOAD_CWD), keeping them as typed there" in {
    val here = java.nio.file.Paths.get("").toAbsolutePath.toString
    val user = Scratch.dir("user-cwd-")
    assert(Cli.userPath("t.csv", Some(user.toString)) == user.resolve("t.csv"))
    assert(Cli.userPath("../x/t.csv", Some(user.toString)) == user.getParent.resolve("x").resolve("t.csv"))
    assert(Cli.userPath("/abs/t.csv", Some(user.toString)).toString == "/abs/t.csv")
    assert(Cli.userPath("golden/a.csv", Some(here)).toString == "golden/a.csv")
    assert(Cli.userPath("golden/a.csv", None).toString == "golden/a.csv")
    // The options go through it, and a missing file's error says where it looked.
    val cli = Cli.parse("simulate", Seq("--input", "t.csv"), Simulate.options)
    assert(cli.path("input").get.toString == Cli.userPath("t.csv").toString)
    val e = intercept[InputError](params("--config", "no/such.conf"))
    assert(
      e.getMessage.contains(s"looked for ${java.nio.file.Paths.get("no/such.conf").toAbsolutePath}"),
      e.getMessage
    )
  }

  it should "say a directory given as --config or --robot is a directory, and where a missing robot was looked for" in {
    val dir = Scratch.dir("a-dir-")
    def refused(args: Seq[String], words: String*): Unit = {
      val e = intercept[InputError](compiled(args: _*))
      words.foreach(w => assert(e.getMessage.contains(w), e.getMessage))
      assert(!e.getMessage.contains("\n"), e.getMessage)
    }
    refused(Seq("--config", dir.toString), dir.toString, "is a directory")
    val conf = Scratch.file("robot-dir", ".conf")
    Files.write(conf, s"robot.source = \"$dir\"\nrobot.max-acceleration = 5\n".getBytes("UTF-8"))
    refused(Seq("--config", conf.toString), conf.toString, "robot.source", "is a directory")
    refused(Seq("--robot", dir.toString, "--max-acceleration", "5"), "--robot", "is a directory")
    refused(
      Seq("--robot", "no/such.urdf", "--max-acceleration", "5"),
      "no such file",
      java.nio.file.Paths.get("no/such.urdf").toAbsolutePath.toString
    )
  }

  it should "name settings by their keys, never by internal fields, in a refusal" in {
    Seq(
      Seq("--robot", "planar3", "--max-acceleration", "[10, -1, 10]"),
      Seq("--robot", "planar3", "--max-velocity", "[3, 0, 3]"),
      Seq("--robot", "planar3", "--max-acceleration", "[10, 10]")
    ).foreach { args =>
      val e = intercept[InputError](compiled(args: _*))
      assert(e.getMessage.contains("max-"), e.getMessage)
      assert("[a-z][A-Z]|Params".r.findFirstIn(e.getMessage).isEmpty, s"an internal name in: ${e.getMessage}")
    }
  }

  it should "make ./sbt refuse an unquoted option after run (./sbt run --help) before anything starts" in {
    // No PATH: were the check missing, the script would fail at its first external command instead.
    val err = new StringBuilder
    val status = scala.sys.process
      .Process(Seq("/bin/bash", "./sbt", "run", "--help"), None, "PATH" -> "/nonexistent")
      .!(scala.sys.process.ProcessLogger(_ => (), l => err.append(l).append('\n')))
    assert(status == 2, err.toString)
    assert(
      err.toString.contains("./sbt \"run --help\"") && err.toString.linesIterator.size == 1,
      err.toString
    )
    val runMain = scala.sys.process
      .Process(Seq("/bin/bash", "./sbt", "--error", "runMain", "-x"), None, "PATH" -> "/nonexistent")
      .!(scala.sys.process.ProcessLogger(_ => (), _ => ()))
    assert(runMain == 2)
  }

  it should "keep the shipped presets of every kind loadable" in {
    LoadParams.allPresets.foreach { case (name, p) =>
      assert(params("--preset", name) == p, name)
    }
  }
}
