package reducerload.app

import reducerload.compiler.Compiled
import reducerload.regmap.{MarkdownReference, ReducerLoadRegisters}

/**
 * The generated part of docs/register-map.md: the register reference of an example design (the monitored
 * planar arm). `./sbt --error "runMain reducerload.app.RegisterMapDoc"` prints it; DocsFreshnessSpec checks
 * docs/register-map.md holds exactly this text.
 */
object RegisterMapDoc {
  val key = "./sbt --error \"runMain reducerload.app.RegisterMapDoc\""

  /**
   * planar3 with the reducer monitor, thresholds below its loads so that the limit flags fire: the monitored
   * design of the docs' examples and of the tests (soak, ports, lint, replay, register map).
   */
  val monitoredPlanar3: Seq[String] = Seq(
    "--robot",
    "planar3",
    "--monitor.enabled",
    "true",
    "--monitor.repeated-peak",
    "[80, 30, 20]",
    "--monitor.momentary-peak",
    "[100, 40, 28]"
  )

  /** The example design's command-line settings (the register-map tests build the same design). */
  val exampleArgs: Seq[String] = monitoredPlanar3 ++ Seq("--monitor.exponent", "[3, 3.3333333333333335, 1.5]")

  def example: Compiled = Cli.parse("emit", exampleArgs, Emit.options).compiled

  /** The reference's lines with its headings two levels down, to sit under the document's own. */
  def lines: Seq[String] = {
    val command =
      "./sbt \"run emit " + exampleArgs.map(a => if (a.contains(' ')) s"'$a'" else a).mkString(" ") + "\""
    MarkdownReference(ReducerLoadRegisters(example), command).linesIterator.map { l =>
      if (l.startsWith("#")) "##" + l else l
    }.toSeq
  }

  def main(args: Array[String]): Unit =
    println(
      (s"<!-- generated: $key (checked by DocsFreshnessSpec) -->" +: lines :+ "<!-- end generated -->")
        .mkString("\n")
    )
}
