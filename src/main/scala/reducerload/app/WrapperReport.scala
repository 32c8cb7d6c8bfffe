package reducerload.app

import reducerload.compiler.Compiled
import reducerload.config.BusKind
import reducerload.regmap.{ReducerLoadRegisters, StreamLayout, WrapperPort, WrapperPorts}

/**
 * The report of a `reducer_load` wrapper emission: the wrapper's ports (named from its Bundles) and stream
 * bit layouts first, then the datapath's report (`datapath`: its module, ports and resources) beside it.
 */
final case class WrapperReport(c: Compiled, moduleName: String, datapath: ArmReport) extends EmissionReport {
  private val map = ReducerLoadRegisters(c)
  def latency: Int = datapath.latency
  def throughput: String = datapath.throughput
  val bus: BusKind = c.config.bus.kind
  val ports: Seq[WrapperPort] = bus match {
    case BusKind.Axi => WrapperPorts.axi(c.arm, map)
    case _           => WrapperPorts.avalon(c.arm, map)
  }
  private def layout(title: String, fields: Seq[reducerload.regmap.StreamField]) =
    s"$title: " + fields.map(f => s"${f.name}[${f.msb}:${f.lsb}]").mkString(" ")

  def portLines: Seq[String] =
    Seq(s"Wrapper ${bus.name}: ports") ++ ports.map(p =>
      f"  ${p.name}%-26s ${p.direction}%-3s ${p.width}%d bits"
    ) ++
      Seq(
        layout("Input beat (one sample)", StreamLayout.input(c.arm)),
        layout("Output beat", StreamLayout.output(c.arm)),
        s"Registers: ${4 * map.words} bytes (${map.name}_regs.h / .md / .rdl)"
      )

  def summaryLines: Seq[String] =
    Seq("", s"Inside: ${datapath.moduleName}") ++ datapath.portLines ++ Seq("") ++ datapath.summaryLines

  def markdown: String =
    (Seq(
      s"# $moduleName (${bus.name} wrapper of ${datapath.moduleName})",
      "",
      "## Wrapper ports",
      "",
      "| port | dir | bits |",
      "| --- | --- | --- |"
    ) ++ ports.map(p => s"| `${p.name}` | ${p.direction} | ${p.width} |") ++ Seq(
      "",
      "## Stream layouts (bit ranges, from bit 0)",
      "",
      "- " + layout("in", StreamLayout.input(c.arm)),
      "- " + layout("out", StreamLayout.output(c.arm)),
      ""
    )).mkString("", "\n", "\n") + datapath.markdown.replaceFirst("(?m)^# ", "# Inside: ")

  def json: String = {
    val wrapper = "{\"top\": \"" + moduleName + "\", \"bus\": \"" + bus.name + "\", \"ports\": [" +
      ports
        .map(p => s"""{"name": "${p.name}", "direction": "${p.direction}", "width": ${p.width}}""")
        .mkString(", ") +
      "], \"datapath\": "
    wrapper + datapath.json.trim + "}\n"
  }
}
