package reducerload.api

import chisel3._
import circt.stage.ChiselStage
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.app.{Cli, Emit, Top}
import reducerload.arm.ArmDatapath
import reducerload.monitor.MonitoredArm
import reducerload.util.InputError

import java.nio.file.{Files, Paths}

class ReducerLoadSpec extends AnyFlatSpec {
  behavior of "ReducerLoad"

  private val args = Seq("--preset", "smallest", "--robot", "planar3", "--bus", "none")

  it should "build the design the command line emits, with its report, inside another module" in {
    val core = ReducerLoad.fromArgs(args: _*)
    val cli = Emit.emit(Cli.parse("emit", args, Nil).compiled, Top.Load, "cmd")
    assert(core.moduleName == cli.topModule)
    assert(core.report.moduleName == cli.topModule && core.report.latency == core.latency)
    assert(core.report.markdown.contains(core.command))
    assert(core.clocksPerSample == 3)
    class Parent extends Module {
      val in = IO(Input(UInt(8.W)))
      val out = IO(Output(UInt(8.W)))
      out := RegNext(in) // logic of its own beside the core
      val load = Module(core.module[ArmDatapath])
      load.io.in.noenq()
    }
    val sv = ChiselStage.emitSystemVerilog(new Parent, Array.empty[String], Emit.firtoolOpts)
    assert(sv.contains(s"module ${core.moduleName}(") && sv.contains("module Parent("))
  }

  it should "choose the top as emission does: the monitored arm with the monitor; typed settings too" in {
    val monitored = ReducerLoad.fromArgs(reducerload.testutil.monitoredPlanar3 ++ Seq("--bus", "none"): _*)
    assert(monitored.moduleName == s"MonitoredArm_${monitored.compiled.arm.tag}")
    assert(monitored.report.markdown.contains("monitor"))
    val typed = ReducerLoad(reducerload.config.LoadParams.smallest)
    // The default bus wraps the core in the stable `reducer_load` top, as `run emit` does.
    assert(typed.moduleName == "reducer_load" && typed.compiled.arm.moduleName.startsWith("LoadDatapath_"))
    assert(typed.config.contains("angle-bits = 16"))
  }

  it should "name the top's class when asked for another" in {
    val core = ReducerLoad.fromArgs(args: _*)
    class Parent extends Module { val load = Module(core.module[MonitoredArm]) }
    val e = intercept[Exception](ChiselStage.emitCHIRRTL(new Parent))
    val cause =
      Iterator.iterate[Throwable](e)(_.getCause).takeWhile(_ != null).collectFirst { case i: InputError => i }
    assert(cause.exists(_.getMessage.contains("is ArmDatapath")), e)
  }

  it should "build a robot shipped in the jar from its resources, not the repository's golden/" in {
    val core = ReducerLoad(
      Robot.Ur5,
      Seq("--tip", "tool0", "--max-acceleration", "15", "--bus", "none") ++
        reducerload.testutil.PayloadDesigns.scheduleArgs: _*
    )
    assert(core.compiled.arm.chain.size == 6)
    assert(core.moduleName.startsWith("ArmDatapath_ur5_6dof"), core.moduleName)
    assert(!Robot.Ur5.file.toAbsolutePath.startsWith(Paths.get("").toAbsolutePath), Robot.Ur5.file)
    assert(Robot("panda") == Robot.Panda && Robot("planar3") == Robot.Planar3)
    assert(Robot("my.urdf") == Robot.Urdf(Paths.get("my.urdf")))
  }

  it should "refuse bad input with the command line's one-line message" in {
    def message(f: => Any) = intercept[InputError](f).getMessage
    val bad = Seq("--preset", "smallest", "--cordic.iterations", "1")
    assert(message(ReducerLoad.fromArgs(bad: _*)) == message(Cli.parse("emit", bad, Nil).compiled))
    assert(message(ReducerLoad(Robot.Ur5)).contains("declare --max-acceleration"))
    assert(message(ReducerLoad.fromArgs("--top", "load")).contains("unknown option --top"))
  }

  it should "be what examples/ and docs/library.md depend on: the build's coordinates and versions" in {
    def text(f: String) = new String(Files.readAllBytes(Paths.get(f)), "UTF-8")
    val build = text("build.sbt")
    def setting(key: String) =
      raw"""(?m)^\s*(?:val |ThisBuild / )?$key :?= "([^"]+)"""".r
        .findFirstMatchIn(build)
        .map(_.group(1))
        .getOrElse(
          fail(s"build.sbt sets no $key")
        )
    val coordinates = s""""${setting("organization")}" %% "${setting("name")}" % "${setting("version")}""""
    val example = text("examples/build.sbt")
    assert(example.contains(coordinates), s"examples/build.sbt does not depend on $coordinates")
    Seq("scalaVersion", "chiselVersion").foreach(k => assert(example.contains(s"\"${setting(k)}\""), k))
    assert(text("examples/project/build.properties") == text("project/build.properties"))
    assert(text("docs/library.md").contains(coordinates), s"docs/library.md does not show $coordinates")
  }
}
