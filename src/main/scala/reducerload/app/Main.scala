package reducerload.app

import reducerload.config.{LoadParams, RobotDefaults, Settings}
import reducerload.util.InputError

/**
 * `./sbt "run [command] [options]"`. Commands: emit (default), simulate, help. User mistakes end with one
 * line `error: ...` and exit status 2; nothing partial is written.
 */
/**
 * A command word of `./sbt "run ..."`: its help line, its own options and switches, whether it takes the
 * design options and settings flags, and what it does with the parsed command line.
 */
sealed abstract class Command(
    val name: String,
    val help: String,
    val options: Seq[Opt] = Nil,
    val flags: Seq[String] = Nil,
    val flagHelp: Map[String, String] = Map.empty,
    val design: Boolean = true
) {
  def run(cli: Cli, commandLine: String): Unit
}

object Command {
  case object EmitDesign
      extends Command(
        "emit",
        "emit SystemVerilog, report.md, report.json and config.conf",
        Emit.options,
        Emit.flags,
        Simulate.flagHelp ++ Emit.flagHelp
      ) {
    def run(cli: Cli, commandLine: String): Unit = Emit.run(cli, commandLine)
  }

  case object SimulateTrajectory
      extends Command(
        "simulate",
        "stream a trajectory CSV through the RTL on Verilator and compare with the reference",
        Simulate.options,
        Simulate.flags,
        Simulate.flagHelp ++ Emit.flagHelp
      ) {
    def run(cli: Cli, commandLine: String): Unit = Simulate.run(cli)
  }

  case object WriteTrajectory
      extends Command(
        "trajectory",
        "write a seeded random trajectory CSV within the design's declared ranges (for simulate benchmarks)",
        Trajectory.options
      ) {
    def run(cli: Cli, commandLine: String): Unit = Trajectory.run(cli)
  }

  case object SweepDesigns
      extends Command(
        "sweep",
        "design-space benchmark: error, latency, resources (and Fmax) over a grid; CSV, markdown, plots",
        Sweep.options,
        Sweep.flags,
        Sweep.flagHelp,
        design = false
      ) {
    def run(cli: Cli, commandLine: String): Unit = Sweep.run(cli)
  }

  case object SoakRtl
      extends Command(
        "soak",
        "stream many seeded random samples (bubbles, resets, out-of-range inputs) through the RTL, check each against the model",
        Soak.options
      ) {
    def run(cli: Cli, commandLine: String): Unit = Soak.main(cli)
  }

  case object PrintConfig
      extends Command(
        "config",
        "print the effective configuration as a complete HOCON file (a starting point for --config)"
      ) {
    def run(cli: Cli, commandLine: String): Unit = {
      val header =
        if (cli.overrides.isEmpty && !cli.has("config"))
          Main.presetHeader(cli.get("preset").getOrElse("default"))
        else Seq("Configuration of the reducer-load generator, from:", s"  $commandLine")
      // Compiled, so that a configuration that cannot be built is refused here too.
      print(Settings.render(cli.compiled.config, header))
    }
  }

  case object ConfigurationDoc
      extends Command(
        "configuration-doc",
        "print docs/configuration.md, the settings reference (markdown)",
        design = false
      ) {
    def run(cli: Cli, commandLine: String): Unit = print(reducerload.config.SettingsDoc.markdown)
  }

  case object PresetsTable
      extends Command(
        "presets-table",
        "print the README's preset table (markdown; measures each preset on the golden traces)",
        design = false
      ) {
    def run(cli: Cli, commandLine: String): Unit = println(reducerload.app.PresetsTable.markdown)
  }

  /** In the order of --help. */
  val all: Seq[Command] = Seq(
    EmitDesign,
    SimulateTrajectory,
    WriteTrajectory,
    SweepDesigns,
    SoakRtl,
    PrintConfig,
    ConfigurationDoc,
    PresetsTable
  )
}

object Main {

  /** The header of a shipped preset file: how to regenerate it. */
  def presetHeader(name: String): Seq[String] = Seq(
    s"Preset '$name' of the reducer-load generator. Regenerate with:",
    s"  ./sbt --error \"run config --preset $name\" > configs/$name.conf"
  )

  def help: String = {
    val settings = Settings.all.map { s =>
      val flags = (s.key +: s.aliases.filterNot(_ == s.key)).map("--" + _).mkString(", ")
      val unit = if (s.unit.nonEmpty) s" [${s.unit}]" else ""
      val robot = RobotDefaults.note(s).fold("")(v => s"; with --robot FILE: $v")
      f"  $flags%-42s ${s.typeName}: ${s.help}$unit (default ${s.render(LoadParams.default)}$robot)"
    }
    (Seq(
      "reducer-load generator: a real-time robot reducer-load calculator (CORDIC + load datapath) for FPGAs",
      "",
      "usage: ./sbt \"run [command] [options]\"",
      "",
      "commands:"
    ) ++ Command.all.map(c => f"  ${c.name}%-15s ${c.help}") ++ Seq(f"  ${"help"}%-15s this text", "") ++
      Command.all.filter(c => c.options.nonEmpty || c.flags.nonEmpty).flatMap { c =>
        s"${c.name} options:" +: (c.options.map(o =>
          f"  ${s"--${o.name} ${o.arg}"}%-34s ${o.help}" + (if (o.default.nonEmpty)
                                                              s" (default ${o.default})"
                                                            else "")
        ) ++
          c.flags.map(f => f"  ${"--" + f}%-34s ${c.flagHelp.getOrElse(f, "")}")) :+ ""
      } ++ Seq("design options (emit, simulate, soak, config):") ++ Cli.designOptions.map(o =>
        f"  ${s"--${o.name} ${o.arg}"}%-34s ${o.help}"
      ) ++
      Seq("", "settings (override the preset or config file):") ++ settings).mkString("\n")
  }

  def run(args: Seq[String]): Unit = {
    val (command, rest) = args.toList match {
      case Nil                                     => ("emit", Nil)
      case ("--help" | "-h" | "help") :: _         => ("help", Nil)
      case first :: tail if !first.startsWith("-") => (first, tail)
      case all                                     => ("emit", all)
    }
    val commandLine =
      "./sbt \"run " + (command +: rest.map(a => if (a.exists(_.isWhitespace)) s"'$a'" else a))
        .mkString(" ") + "\""
    if (command == "help") println(help)
    else
      Command.all.find(_.name == command) match {
        case Some(c) => c.run(Cli.parse(c.name, rest, c.options, c.flags, c.design), commandLine)
        case None =>
          throw new InputError(
            s"command line: unknown command '$command' (commands: ${(Command.all.map(_.name) :+ "help").mkString(", ")})"
          )
      }
  }

  /**
   * Run a command line and return its exit status, a refusal printed on `err` as its one line; no
   * System.exit, so that tests run the real command line in-process.
   */
  def execute(args: Seq[String], err: java.io.PrintStream = System.err): Int =
    try { Console.withErr(err)(run(args)); 0 }
    catch {
      case e: InputError => err.println(s"error: ${e.getMessage}"); 2
      case e: IllegalArgumentException =>
        err.println(s"error: ${e.getMessage.stripPrefix("requirement failed: ")}"); 2
      // A derived bound that a result exceeds: not the user's mistake, but one line and a distinct status.
      case e: IllegalStateException => err.println(s"failed check: ${e.getMessage}"); 1
    }

  def main(args: Array[String]): Unit = {
    val status = execute(args.toSeq)
    System.out.flush()
    if (status != 0) sys.exit(status)
  }
}
