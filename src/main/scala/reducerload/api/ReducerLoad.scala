package reducerload.api

import chisel3.RawModule
import reducerload.app.{Cli, EmissionReport, Emit, TopModule}
import reducerload.arm.ArmModel
import reducerload.compiler.{Compiled, Compiler}
import reducerload.config.{LoadParams, Settings}
import reducerload.pipeline.MultiplierImpl
import reducerload.robot.RobotParams
import reducerload.util.InputError

import java.nio.file.{Files, Path}
import scala.reflect.ClassTag

/**
 * A robot to build the core for: the built-in planar3, a URDF file, or a URDF the library ships in its jar
 * (found from any working directory).
 */
sealed trait Robot {

  /** What `--robot` takes for it in [[ReducerLoad.fromArgs]]. */
  def argument: String
}

object Robot {
  case object Planar3 extends Robot {
    def argument: String = RobotParams.planar3
  }

  /** A URDF file (a relative path is relative to the process's working directory). */
  final case class Urdf(path: Path) extends Robot {
    def argument: String = path.toString
  }

  /**
   * A URDF shipped as a resource under `reducerload/robots/` (with its licence; golden/robots/README.md),
   * copied out once per JVM: the settings' `robot.source` is a file path.
   */
  sealed abstract class Bundled(val argument: String, resource: String) extends Robot {
    lazy val file: Path = {
      val in = getClass.getResourceAsStream(s"/reducerload/robots/$resource")
      require(
        in != null,
        s"the library's reducerload/robots/$resource resource is missing (build.sbt copies it)"
      )
      val f = copies.resolve(resource)
      try Files.copy(in, f)
      finally in.close()
      f.toFile.deleteOnExit()
      f
    }
  }
  case object Ur5 extends Bundled("ur5", "ur5_robot.urdf")
  case object Panda extends Bundled("panda", "panda.urdf")

  val bundled: Seq[Bundled] = Seq(Ur5, Panda)

  private lazy val copies: Path = {
    val d = Files.createTempDirectory("reducerload-robots")
    d.toFile.deleteOnExit()
    d
  }

  /** `planar3`, a bundled robot's name ([[bundled]]), else the path of a URDF file. */
  def apply(text: String): Robot =
    if (text == RobotParams.planar3) Planar3
    else bundled.find(_.argument == text).getOrElse(Urdf(java.nio.file.Paths.get(text)))
}

/**
 * A core built from a robot and settings: the compiled design, its top module for `Module(...)` inside
 * another Chisel design, its report, and the bit-accurate model its outputs equal.
 *
 * @param command
 *   how to build it again, for the report's "regenerate with" line
 */
final class Core private[api] (val compiled: Compiled, val command: String) {

  /**
   * The top module's name and generator, the one `./sbt "run emit"` emits for the same settings. With
   * `MultiplierImpl.ChiselTwin` in implicit scope, the multiplies are Chisel (for treadle, which cannot run
   * the Verilog black box).
   */
  def top(implicit multiplierImpl: MultiplierImpl): TopModule = Emit.topModule(compiled)

  /** The top module's name (its `desiredName`). */
  def moduleName: String = top.name

  /**
   * A fresh instance of the top as the class `M` it is for these settings: `Module(core.module[ArmDatapath])`
   * in a parent; a settings choice that makes another top (the monitor: `MonitoredArm`) is an [[InputError]]
   * naming both.
   */
  def module[M <: RawModule](implicit tag: ClassTag[M], multiplierImpl: MultiplierImpl): M =
    top.generator() match {
      case m: M => m
      case other =>
        throw new InputError(
          s"$command: the top for these settings is ${other.getClass.getSimpleName} (${top.name}), not ${tag.runtimeClass.getSimpleName}"
        )
    }

  /** Ports, formats, latency, clocks per sample, error bounds: what `report.md` and `report.json` hold. */
  lazy val report: EmissionReport = Emit.loadReport(compiled, command)

  /** The datapath's bit-accurate model: sample encoding, torque codes, torques in N·m. */
  lazy val model: ArmModel = new ArmModel(compiled.arm)

  /** Clocks from a sample taken on `io.in` to its torques on `io.out`. */
  def latency: Int = compiled.arm.latency

  /** Clocks between samples (`io.in.ready` is high one clock in this many). */
  def clocksPerSample: Int = compiled.arm.schedule.clocksPerSample

  /** The effective configuration, as `config.conf` holds it. */
  def config: String =
    Settings.render(compiled.config, Seq("Effective configuration; build again with:", s"  $command"))
}

/**
 * The library's entry point: build the reducer-load core inside another Chisel design.
 *
 * {{{
 * val core = ReducerLoad.fromArgs("--preset", "smallest")
 * class MyTop extends Module {
 *   val load = Module(core.module[ArmDatapath])
 *   // connect load.io.in (ready/valid samples) and load.io.out (valid torques)
 * }
 * }}}
 *
 * Bad input throws [[InputError]] with the line `./sbt "run emit"` prints for the same settings.
 */
object ReducerLoad {

  /**
   * What `./sbt "run emit ..."` takes for its design: `--preset NAME` or `--config FILE`, `--robot` (also a
   * bundled robot's name, [[Robot.bundled]]) and every settings flag (`--key value` or `--key=value`).
   */
  def fromArgs(args: String*): Core = {
    val cli = Cli.parse("emit", args, Nil)
    // A bundled robot's name becomes its copied file before the command line's checks see it.
    val bundled = cli.overrides.map {
      case (key, value) if key == Settings.robotSource.key =>
        key -> (Robot(value) match {
          case b: Robot.Bundled => b.file.toString
          case _                => value
        })
      case kv => kv
    }
    val command = args.map(a => "\"" + a.replace("\\", "\\\\").replace("\"", "\\\"") + "\"").mkString(", ")
    new Core(cli.copy(overrides = bundled).compiled, s"reducerload.api.ReducerLoad.fromArgs($command)")
  }

  /** `robot` with the settings flags `settings` (as [[fromArgs]] takes them after `--robot`). */
  def apply(robot: Robot, settings: String*): Core = fromArgs(Seq("--robot", robot.argument) ++ settings: _*)

  /** Typed settings (a preset of `LoadParams.allPresets`, changed with `copy`). */
  def apply(params: LoadParams): Core =
    new Core(Compiler.compile(params, "ReducerLoad(params)"), "reducerload.api.ReducerLoad(params)")
}
