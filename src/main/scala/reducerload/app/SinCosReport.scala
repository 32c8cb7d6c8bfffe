package reducerload.app

import com.typesafe.config.{ConfigRenderOptions, ConfigValueFactory}
import chisel3.Data
import reducerload.cordic.{CordicParams, CordicSinCosIO}
import reducerload.fixedpoint.FixedFormat
import reducerload.sim.rtl.ModulePorts

import scala.jdk.CollectionConverters._

/** The report of a lone CORDIC sin/cos unit's emission (`--top sincos`); datapaths have [[ArmReport]]. */
final case class SinCosReport(
    c: CordicParams,
    moduleName: String,
    command: String,
    estimate: Option[Estimate] = None
) extends EmissionReport {
  def latency: Int = c.latency
  val throughput: String = "one angle per clock"

  private val io = new CordicSinCosIO(c)
  private val table = new PortTable(moduleName, ModulePorts(io))

  /** Every port of the module once, named from its IO Bundle, with its format. */
  val ports: Seq[PortRow] = {
    def at(leaf: Data, text: String) = table(leaf, text)
    val described = table.clockAndReset ++ Seq(
      at(io.in.valid, "1 bit"),
      at(io.in.bits, s"unsigned ${c.angleBits} bits, binary angle"),
      at(io.out.valid, s"1 bit, ${c.latency} cycles after the angle"),
      at(io.out.bits.cos, c.outputFormat.describe),
      at(io.out.bits.sin, c.outputFormat.describe)
    )
    table.complete(described)
  }

  def portLines: Seq[String] = table.lines(ports, 24)

  def summaryLines: Seq[String] = estimate.toSeq.flatMap(_.lines) ++ c.report.linesIterator.toSeq

  def markdown: String = (Seq(
    s"# $moduleName",
    "",
    s"- latency: ${c.latency} cycles; throughput: $throughput",
    f"- derived error bound: ${c.errorBound}%.3e",
    s"- regenerate: `$command`",
    "",
    "## Ports",
    "",
    "| port | dir | format |",
    "| --- | --- | --- |"
  ) ++ table.markdown(ports) ++ Seq(
    "",
    "## Details",
    "",
    "```"
  ) ++ summaryLines ++ Seq("```"))
    .mkString("", "\n", "\n")

  def json: String = {
    def fmt(f: FixedFormat) =
      Map("int_bits" -> f.intBits, "frac_bits" -> f.fracBits, "width" -> f.width).asJava
    val fields = Map[String, Any](
      "top" -> moduleName,
      "latency_cycles" -> c.latency,
      "clocks_per_sample" -> 1,
      "command" -> command,
      "cordic" -> Map(
        "tag" -> c.tag,
        "angle_bits" -> c.angleBits,
        "output_format" -> fmt(c.outputFormat),
        "iterations" -> c.iterations,
        "iterations_per_stage" -> c.iterationsPerStage,
        "latency_cycles" -> c.latency,
        "gain_k" -> c.gainK,
        "error_bound" -> c.errorBound,
        "atan_table_hex" -> c.atanTable.map(_.toString(16)).asJava
      ).asJava,
      "estimate" -> estimate.map(_.toMap.asJava).orNull
    )
    ConfigValueFactory
      .fromMap(fields.asJava)
      .render(ConfigRenderOptions.concise().setJson(true).setFormatted(true)) + "\n"
  }
}
