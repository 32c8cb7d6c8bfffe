package reducerload.app

import com.typesafe.config.{ConfigRenderOptions, ConfigValueFactory}
import reducerload.fixedpoint.FixedFormat
import reducerload.load.LoadParams

import scala.jdk.CollectionConverters._

/** The report of one emission, computed from the same parameters that built the hardware. */
final case class Report(p: LoadParams, top: Top, moduleName: String, latency: Int, command: String, estimate: Option[Estimate] = None) {
  private val c = p.cordic

  /** (port, direction, format description). */
  val ports: Seq[(String, String, String)] = {
    val clockReset = Seq(("clock", "in", "1 bit"), ("reset", "in", "1 bit, synchronous, active high: clears every valid bit"))
    top match {
      case Top.Load =>
        val angles = Seq("t1", "t2", "t3").map(n =>
          (s"io_in_bits_$n", "in", s"unsigned ${p.angleBits} bits, binary angle: rad = code * 2 pi / 2^${p.angleBits}"))
        val vel = Seq("d1", "d2", "d3").zip(p.velocityFormats).zip(p.robot.maxVelocity).map { case ((n, f), m) =>
          (s"io_in_bits_$n", "in", s"${f.describe}, rad/s, declared |$n| <= $m")
        }
        val acc = Seq("dd1", "dd2", "dd3").zip(p.accelerationFormats).zip(p.robot.maxAcceleration).map { case ((n, f), m) =>
          (s"io_in_bits_$n", "in", s"${f.describe}, rad/s^2, declared |$n| <= $m")
        }
        val ready =
          if (p.samplePeriod == 1) "1 bit: always high (one sample per clock)"
          else s"1 bit: low for the ${p.samplePeriod - 1} clocks after a sample is taken (one shared CORDIC unit)"
        clockReset ++ Seq(("io_in_valid", "in", "1 bit: a sample this cycle (taken when io_in_ready is high)"), ("io_in_ready", "out", ready)) ++
          angles ++ vel ++ acc ++ Seq(
          ("io_out_valid", "out", s"1 bit: the load of the sample given $latency cycles earlier"),
          ("io_out_bits_load", "out", s"${p.outputFormat.describe}, N·m"),
          ("io_out_bits_outOfRange", "out", "1 bit: an input of this sample was beyond its declared range (clamped)")
        )
      case Top.SinCos =>
        clockReset ++ Seq(
          ("io_in_valid", "in", "1 bit"),
          ("io_in_bits", "in", s"unsigned ${c.angleBits} bits, binary angle"),
          ("io_out_valid", "out", s"1 bit, $latency cycles after the angle"),
          ("io_out_bits_cos", "out", c.outputFormat.describe),
          ("io_out_bits_sin", "out", c.outputFormat.describe)
        )
    }
  }

  def portLines: Seq[String] = "Ports:" +: ports.map { case (n, d, f) => f"  $n%-24s $d%-3s $f" }

  private def constants: Seq[(String, Double, BigInt)] = Seq(
    ("A = m3 l1 l3", p.robot.a, p.constA),
    ("B = m3 l2 l3", p.robot.b, p.constB),
    ("C = m3 l3^2", p.robot.c, p.constC),
    ("D = m3 g l3", p.robot.d, p.constD)
  )

  def summaryLines: Seq[String] = estimate.toSeq.flatMap(_.lines) ++ designLines

  private def designLines: Seq[String] = top match {
    case Top.Load =>
      Seq(
        s"Model: ${p.model.description}",
        f"Robot: m3=${p.robot.m3} kg, l1=${p.robot.l1} m, l2=${p.robot.l2} m, l3=${p.robot.l3} m, g=${p.robot.g} m/s^2",
        f"Load range (sum of term maxima): ${p.loadRange}%.3f N·m; output ${p.outputFormat}",
        f"Derived worst-case error bound: ${p.errorBound}%.3e N·m (vs exact double-precision formula at the unquantized inputs)",
        "Folded constants:"
      ) ++ constants.map { case (n, v, raw) =>
        f"  $n%-14s = $v%.9f -> 0x${raw.toString(16)} * 2^-${p.constantFracBits} = ${FixedFormat.scaleDown(raw, p.constantFracBits)}%.9f"
      } ++ c.report.linesIterator.toSeq
    case Top.SinCos => c.report.linesIterator.toSeq
  }

  def markdown: String = {
    val nodes = p.formats.toSeq.sortBy(_._1)
    val sb = Seq(
      s"# $moduleName",
      "",
      s"- latency: $latency cycles; throughput: ${Report.throughput(p, top)}",
      f"- derived error bound: ${if (top == Top.Load) p.errorBound else c.errorBound}%.3e ${if (top == Top.Load) "N·m" else ""}",
      s"- regenerate: `$command`",
      "",
      "## Ports",
      "",
      "| port | dir | format |",
      "| --- | --- | --- |"
    ) ++ ports.map { case (n, d, f) => s"| `$n` | $d | $f |" } ++ Seq("", "## Details", "", "```") ++ summaryLines ++ Seq("```") ++
      (if (top == Top.Load)
         Seq("", "## Internal formats (derived from the declared ranges)", "", "| node | format | width |", "| --- | --- | --- |") ++
           nodes.map { case (n, f) => s"| $n | $f | ${f.width} |" }
       else Nil)
    sb.mkString("", "\n", "\n")
  }

  def json: String = {
    def fmt(f: FixedFormat) = Map("int_bits" -> f.intBits, "frac_bits" -> f.fracBits, "width" -> f.width).asJava
    val common = Map[String, Any](
      "top" -> moduleName,
      "latency_cycles" -> latency,
      "clocks_per_sample" -> (if (top == Top.Load) p.samplePeriod else 1),
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
      ).asJava
    )
    val load = if (top == Top.Load) Map[String, Any](
      "model" -> p.model.name,
      "robot" -> Map("m3" -> p.robot.m3, "l1" -> p.robot.l1, "l2" -> p.robot.l2, "l3" -> p.robot.l3, "g" -> p.robot.g,
        "max_velocity" -> p.robot.maxVelocity.map(Double.box).asJava, "max_acceleration" -> p.robot.maxAcceleration.map(Double.box).asJava).asJava,
      "error_bound_nm" -> p.errorBound,
      "load_range_nm" -> p.loadRange,
      "output_format" -> fmt(p.outputFormat),
      "velocity_formats" -> p.velocityFormats.map(fmt).asJava,
      "acceleration_formats" -> p.accelerationFormats.map(fmt).asJava,
      "node_formats" -> p.formats.map { case (k, f) => k -> fmt(f) }.asJava,
      "constants" -> constants.map { case (n, v, raw) => Map("name" -> n, "value" -> v, "raw_hex" -> raw.toString(16), "frac_bits" -> p.constantFracBits).asJava }.asJava
    ) else Map.empty[String, Any]
    val est = Map[String, Any]("estimate" -> estimate.map(_.toMap.asJava).orNull)
    ConfigValueFactory.fromMap((common ++ load ++ est).asJava).render(ConfigRenderOptions.concise().setJson(true).setFormatted(true)) + "\n"
  }
}

object Report {

  /** How often the emitted top takes an input, in words. */
  def throughput(p: LoadParams, top: Top = Top.Load): String =
    if (top == Top.SinCos) "one angle per clock"
    else if (p.samplePeriod == 1) "one sample per clock"
    else s"one sample every ${p.samplePeriod} clocks (one CORDIC unit shared by the three angles)"
}
