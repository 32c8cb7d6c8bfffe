package reducerload.monitor

/**
 * The generated part of docs/monitor.md: the example configuration's derivation, 20-year proof and register
 * map. `./sbt --error "runMain reducerload.monitor.MonitorDoc"` prints it; MonitorParamsSpec checks that
 * docs/monitor.md contains exactly this text.
 */
object MonitorDoc {
  val begin =
    "<!-- generated: ./sbt --error \"runMain reducerload.monitor.MonitorDoc\" " +
      "(checked by MonitorParamsSpec) -->"
  val end = "<!-- end generated -->"

  def text: String = {
    val p1k = MonitorParams.example(1e-3)
    val p16k = MonitorParams.example(1.0 / 16000)
    val lines = Seq("### Example: 6 joints at 1 kHz", "", "```") ++ p1k.summaryLines ++ Seq(
      "```",
      "",
      "### The same arm at 16 kHz (widths grow by log2(16) = 4 bits)",
      "",
      "```"
    ) ++ p16k.proofLines ++ Seq(
      "```",
      "",
      s"### Register map (1 kHz example; ${p1k.registerMap.words} words of 32 bits)",
      ""
    ) ++ p1k.registerMap.markdown
    (begin +: lines :+ end).mkString("\n")
  }

  def main(args: Array[String]): Unit = println(text)
}
