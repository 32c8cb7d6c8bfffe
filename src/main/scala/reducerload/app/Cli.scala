package reducerload.app

import com.typesafe.config.{Config, ConfigException, ConfigFactory, ConfigValueFactory}
import reducerload.compiler.{Compiled, Compiler}
import reducerload.config.{Assignment, LoadParams, RobotDefaults, Setting, Settings}
import reducerload.util.{InputError, InputFile}

import java.nio.file.{Path, Paths}
import scala.util.Try

/** A command-line option of a command (settings flags are added to every command that builds a design). */
final case class Opt(name: String, arg: String, help: String, default: String = "")

/** Parsed command line: the command word, option values, and the setting overrides in order. */
final case class Cli(
    command: String,
    options: Map[String, String],
    overrides: Seq[(String, String)],
    args: Seq[String]
) {
  def get(name: String): Option[String] = options.get(name)
  def has(name: String): Boolean = options.contains(name)

  /** The file or directory option `name` names, as [[Cli.userPath]] resolves it. */
  def path(name: String): Option[Path] = options.get(name).map(Cli.userPath(_))

  /** [[path]], or `default` (resolved the same way) when the option is not given. */
  def pathOr(name: String, default: String): Path = path(name).getOrElse(Cli.userPath(default))

  /**
   * The design parameters: a preset or a complete config file, then flag overrides. Only the settings are
   * checked here; [[compiled]] builds the design.
   */
  def params: LoadParams = {
    if (has("preset") && has("config"))
      throw new InputError("command line: --preset and --config are exclusive (a config file is complete)")
    get("config") match {
      case Some(file) =>
        val config = Cli.configFile(file)
        // A robot on the command line replaces the file's, which is then not read.
        val robot =
          if (overrides.exists(_._1 == Settings.robotSource.key)) config
          else Cli.withUserRobotPath(config, file)
        Settings.toParams(robot, source, assignments)
      case None =>
        val name = presetName
        val preset = LoadParams.allPresets.getOrElse(
          name,
          throw new InputError(
            s"command line: --preset '$name' is not a preset (${LoadParams.allPresets.keys.toSeq.sorted.mkString(", ")})"
          )
        )
        Settings.withOverrides(preset, assignments, source)
    }
  }

  /**
   * The design `params` describe, compiled once; a refusal names [[source]]. Its warnings go to standard
   * error, one line each.
   */
  lazy val compiled: Compiled = {
    val c = Compiler.compile(params, source)
    c.warnings.foreach(w => Console.err.println(w)) // Main.execute's error stream
    c
  }

  /** Where the configuration comes from, for error messages. */
  def source: String = {
    val base = get("config").getOrElse(s"preset ${presetName}")
    if (overrides.isEmpty) base else s"$base with command-line overrides"
  }

  // Every joint of a robot starts from the arm preset, unless told otherwise.
  private def presetName: String =
    get("preset").getOrElse(if (overrides.exists(_._1 == "robot.source")) RobotDefaults.preset else "default")

  /** Each override (with those `--robot` implies) parsed to its setting's type, in order. */
  private def assignments: Seq[Assignment[_]] =
    Cli.robotDefaults(overrides).map {
      case (key @ "robot.source", value) if value != reducerload.robot.RobotParams.planar3 =>
        Cli.assign(Settings.byKey(key), Cli.inputFile(userPath = value, what = s"--robot $value").toString)
      case (key, value) => Cli.assign(Settings.byKey(key), value)
    }
}

object Cli {

  /**
   * The directory the user ran `./sbt` from: the script exports it before changing to the repository (sbt
   * runs there), so that relative paths on the command line are the user's.
   */
  val workingDirectoryVariable = "REDUCERLOAD_CWD"

  /**
   * A path from the command line: a relative one is relative to the user's directory `cwd` (by default
   * [[workingDirectoryVariable]]'s). When that is the process's own directory, or unknown, the path is kept
   * as written, so files and reports name it as the user typed it.
   */
  def userPath(text: String, cwd: Option[String] = sys.env.get(workingDirectoryVariable)): Path = {
    val p =
      try Paths.get(text)
      catch {
        case e: java.nio.file.InvalidPathException =>
          throw new InputError(
            s"command line: '${text.filterNot(_.isControl)}' is not a valid path (${e.getReason})"
          )
      }
    val here = Paths.get("").toAbsolutePath.normalize
    cwd.filter(_.nonEmpty).map(d => Paths.get(d).toAbsolutePath.normalize) match {
      case Some(dir) if !p.isAbsolute && dir != here => dir.resolve(p).normalize
      case _                                         => p
    }
  }

  /**
   * An input file named on the command line, resolved by [[userPath]]: refused unless it is a regular file,
   * with the absolute path where it was looked for. `what` names it in the message (a flag, say).
   */
  def inputFile(userPath: String, what: String): Path = {
    val p = Cli.userPath(userPath)
    InputFile.check(p, s"command line: $what")
    p
  }

  /**
   * `--robot X` on the command line means every joint of X: model rnea (unless --model is given), the URDF's
   * velocity limits (unless --max-velocity is given), and no tip carried over from the preset; a URDF has no
   * acceleration limits, so --max-acceleration must be given.
   */
  def robotDefaults(overrides: Seq[(String, String)]): Seq[(String, String)] = {
    val keys = overrides.map(_._1).toSet
    overrides.collectFirst { case ("robot.source", v) => v } match {
      case None => overrides
      case Some(robot) =>
        val planar = robot == reducerload.robot.RobotParams.planar3
        if (!planar && !keys(RobotDefaults.required))
          throw new InputError(
            s"command line: --robot $robot: declare --max-acceleration A or [a1, ..., aN] in rad/s^2 (a URDF has no acceleration limits)"
          )
        // planar3 has no URDF: only the model is implied.
        val implied = RobotDefaults.implied.filter(kv => (kv._1 == "model" || !planar) && !keys(kv._1))
        implied ++ overrides
    }
  }

  /** A configuration file's relative robot.source is the user's path too, as on the command line. */
  private def withUserRobotPath(c: Config, file: String): Config =
    Try(c.getString(Settings.robotSource.key)).toOption
      .filter(_ != reducerload.robot.RobotParams.planar3)
      .fold(c) { v =>
        val p = userPath(v)
        InputFile.check(p, s"$file: ${Settings.robotSource.key} = $v")
        c.withValue(Settings.robotSource.key, ConfigValueFactory.fromAnyRef(p.toString))
      }

  private val strictParse =
    com.typesafe.config.ConfigParseOptions.defaults().setAllowMissing(false)

  /** A configuration file, parsed and resolved; its keys are checked by [[Settings.toParams]]. */
  private def configFile(file: String): Config = {
    val p = userPath(file)
    InputFile.check(p, s"command line: --config $file")
    try ConfigFactory.parseFile(p.toFile, strictParse).resolve()
    catch {
      case e: ConfigException =>
        throw new InputError(s"$file: not a valid HOCON/JSON configuration: ${e.getMessage.split('\n').head}")
    }
  }

  /**
   * A flag's value as its setting's type: the text as the value of a one-key HOCON snippet (a bare list of
   * numbers, a choice or a string quoted as a configuration file would have it), read by the setting itself.
   */
  private def assign[T](setting: Setting[T], value: String): Assignment[T] = {
    val text = setting match {
      case _: Setting.PerJoint | _: Setting.Orientation
          if value.contains(",") && !value.trim.startsWith("[") =>
        s"[$value]"
      case _: Setting.Choice[_] => "\"" + value.replace("\"", "") + "\""
      case _: Setting.Text      => ConfigValueFactory.fromAnyRef(value).render()
      case _                    => value
    }
    val one = Try(ConfigFactory.parseString(s"${setting.key} = $text")).getOrElse(
      throw new InputError(
        s"command line: --${setting.key}: '$value' is not a valid value (${setting.typeName})"
      )
    )
    Assignment(setting, setting.read(one, s"command line --${setting.key}"))
  }

  /** Options every design-building command accepts. */
  val designOptions: Seq[Opt] = Seq(
    Opt(
      "preset",
      "NAME",
      s"start from a shipped preset: ${LoadParams.allPresets.keys.toSeq.sorted.mkString(", ")}",
      "default; arm with --robot"
    ),
    Opt(
      "config",
      "FILE",
      "a complete configuration file (HOCON or JSON, see configs/); exclusive with --preset"
    )
  )

  /**
   * Parse `args` for `command`, accepting its own options, the design options and the settings flags.
   *
   * Hand-written rather than scopt 4: with every option declared and `validate` hooks, scopt still words its
   * own refusals ("Unknown option --x=1", "Unknown argument 'w'", "Missing value after --x") with no hook to
   * replace them, so keeping our one-line `command line: ...` messages would mean matching its English text;
   * and it also accepts `--key:value`. Splitting `--key=value` and `--key value` is all it would take over.
   */
  def parse(
      command: String,
      args: Seq[String],
      own: Seq[Opt],
      flags: Seq[String] = Nil,
      design: Boolean = true
  ): Cli = {
    val valued = (own ++ (if (design) designOptions else Nil)).map(o => o.name -> o).toMap
    @annotation.tailrec
    def loop(
        rest: List[String],
        opts: Map[String, String],
        ovr: Vector[(String, String)],
        pos: Vector[String]
    ): Cli = rest match {
      case Nil => Cli(command, opts, ovr, pos)
      case flag :: tail if flag.startsWith("--") =>
        val (name, inline) = flag.drop(2).split("=", 2) match {
          case Array(n, v) => (n, Some(v))
          case Array(n)    => (n, None)
        }
        def value(): (String, List[String]) = inline match {
          case Some(v) => (v, tail)
          case None =>
            tail match {
              case v :: t if !v.startsWith("--") => (v, t)
              case _ => throw new InputError(s"command line: --$name needs a value")
            }
        }
        if (flags.contains(name)) loop(tail, opts + (name -> "true"), ovr, pos)
        else if (valued.contains(name)) { val (v, t) = value(); loop(t, opts + (name -> v), ovr, pos) }
        else if (design && Settings.byFlag.contains(name)) {
          val (v, t) = value()
          loop(t, opts, ovr :+ (Settings.byFlag(name).key -> v), pos)
        } else if (design && Settings.retired.contains(name))
          throw new InputError(s"command line: --$name is retired: ${Settings.retired(name)}")
        else
          throw new InputError(
            s"command line: unknown option --$name for '$command' (see: ./sbt \"run --help\")"
          )
      case word :: _ =>
        throw new InputError(
          s"command line: unexpected argument '$word' for '$command' (see: ./sbt \"run --help\")"
        )
    }
    loop(args.toList, Map.empty, Vector.empty, Vector.empty)
  }
}
