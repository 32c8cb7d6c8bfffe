package reducerload.app

import reducerload.config.Settings
import reducerload.config.LoadParams
import reducerload.util.InputError

/**
 * `./sbt "run [command] [options]"`. Commands: emit (default), simulate, help. User mistakes end with one
 * line `error: ...` and exit status 2; nothing partial is written.
 */
object Main {
  val commands: Seq[(String, String, Seq[Opt], Seq[String])] = Seq(
    ("emit", "emit SystemVerilog, report.md, report.json and config.conf", Emit.options, Emit.flags),
    (
      "simulate",
      "stream a trajectory CSV through the RTL on Verilator and compare with the reference",
      Simulate.options,
      Simulate.flags
    ),
    (
      "trajectory",
      "write a seeded random trajectory CSV within the design's declared ranges (for simulate benchmarks)",
      Trajectory.options,
      Nil
    ),
    (
      "sweep",
      "design-space benchmark: error, latency, resources (and Fmax) over a grid; CSV, markdown, plots",
      Sweep.options,
      Sweep.flags
    ),
    (
      "soak",
      "stream many seeded random samples (bubbles, resets, out-of-range inputs) through the RTL, check each against the model",
      Soak.options,
      Nil
    ),
    (
      "config",
      "print the effective configuration as a complete HOCON file (a starting point for --config)",
      Nil,
      Nil
    ),
    ("settings-table", "print the README's settings table (markdown)", Nil, Nil),
    (
      "presets-table",
      "print the README's preset table (markdown; measures each preset on the golden traces)",
      Nil,
      Nil
    )
  )

  /** The header of a shipped preset file: how to regenerate it. */
  def presetHeader(name: String): Seq[String] = Seq(
    s"Preset '$name' of the reducer-load generator. Regenerate with:",
    s"  ./sbt --error \"run config --preset $name\" > configs/$name.conf"
  )

  def help: String = {
    val settings = Settings.all.map { s =>
      val flags = (s.key +: s.aliases.filterNot(_ == s.key)).map("--" + _).mkString(", ")
      val unit = if (s.unit.nonEmpty) s" [${s.unit}]" else ""
      f"  $flags%-42s ${s.typeName}: ${s.help}$unit (default ${s.render(LoadParams.default)})"
    }
    (Seq(
      "reducer-load generator: a real-time robot reducer-load calculator (CORDIC + load datapath) for FPGAs",
      "",
      "usage: ./sbt \"run [command] [options]\"",
      "",
      "commands:"
    ) ++ commands.map { case (n, h, _, _) => f"  $n%-15s $h" } ++ Seq(f"  ${"help"}%-15s this text", "") ++
      commands.filter { case (_, _, opts, flags) => opts.nonEmpty || flags.nonEmpty }.flatMap {
        case (n, _, opts, flags) =>
          s"$n options:" +: (opts.map(o =>
            f"  ${s"--${o.name} ${o.arg}"}%-34s ${o.help}" + (if (o.default.nonEmpty)
                                                                s" (default ${o.default})"
                                                              else "")
          ) ++
            flags.map(f =>
              f"  ${"--" + f}%-34s ${(if (n == "sweep") Sweep.flagHelp
                                      else Simulate.flagHelp ++ Emit.flagHelp).getOrElse(f, "")}"
            )) :+ ""
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
    command match {
      case "help"       => println(help)
      case "emit"       => Emit.run(Cli.parse("emit", rest, Emit.options, Emit.flags), commandLine)
      case "simulate"   => Simulate.run(Cli.parse("simulate", rest, Simulate.options, Simulate.flags))
      case "trajectory" => Trajectory.run(Cli.parse("trajectory", rest, Trajectory.options))
      case "sweep"      => Sweep.run(Cli.parse("sweep", rest, Sweep.options, Sweep.flags, design = false))
      case "soak"       => Soak.main(Cli.parse("soak", rest, Soak.options))
      case "settings-table" =>
        Cli.parse("settings-table", rest, Nil, design = false); println(Settings.markdownTable)
      case "presets-table" =>
        Cli.parse("presets-table", rest, Nil, design = false); println(PresetsTable.markdown)
      case "config" =>
        val cli = Cli.parse("config", rest, Nil)
        val header =
          if (cli.overrides.isEmpty && !cli.has("config"))
            presetHeader(cli.get("preset").getOrElse("default"))
          else Seq("Configuration of the reducer-load generator, from:", s"  $commandLine")
        print(Settings.render(cli.compiled.config, header))
      case other =>
        throw new InputError(
          s"command line: unknown command '$other' (commands: ${(commands.map(_._1) :+ "help").mkString(", ")})"
        )
    }
  }

  def main(args: Array[String]): Unit = {
    val status =
      try { run(args.toSeq); 0 }
      catch {
        case e: InputError => System.err.println(s"error: ${e.getMessage}"); 2
        case e: IllegalArgumentException =>
          System.err.println(s"error: ${e.getMessage.stripPrefix("requirement failed: ")}"); 2
        // A derived bound that a result exceeds: not the user's mistake, but one line and a distinct status.
        case e: IllegalStateException => System.err.println(s"failed check: ${e.getMessage}"); 1
      }
    System.out.flush()
    if (status != 0) sys.exit(status)
  }
}
