package reducerload.app

import com.typesafe.config.{Config, ConfigFactory}
import reducerload.util.InputError

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path, Paths}
import scala.sys.process._

/** Figures from tools/estimate/estimate.py (see its README for the method and its limits). */
final case class Estimate(
    les: Int,
    lesArith: Int,
    lesLogic: Int,
    registers: Int,
    mult18x18: Int,
    memoryBits: Int,
    m9kBlocks: Int,
    fmaxEcp5Mhz: Option[Double],
    criticalPath: Option[String],
    yosys: Option[String]
) {

  def lines: Seq[String] = Seq(
    s"Estimated Cyclone IV E resources (open-tool estimate${yosys.fold("")(y => s" by $y")}, tools/estimate/README.md; not a Quartus fit):",
    s"  logic elements ~$les ($lesArith in adders on carry chains, $lesLogic in LUTs, the rest unpacked registers)",
    s"  registers $registers, 18x18 multipliers $mult18x18, memory bits $memoryBits in $m9kBlocks M9K blocks",
    fmaxEcp5Mhz match {
      case Some(f) =>
        f"  Fmax proxy: $f%.1f MHz on a Lattice ECP5-85F speed 6 (nextpnr; compares designs, not a Cyclone IV figure)" +
          criticalPath.map(c => s", critical path $c").getOrElse("")
      case None => "  Fmax proxy: not run (emit --fmax)"
    }
  )

  def toMap: Map[String, Any] = Map(
    "les" -> les,
    "les_arith" -> lesArith,
    "les_logic" -> lesLogic,
    "registers" -> registers,
    "mult18x18" -> mult18x18,
    "memory_bits" -> memoryBits,
    "m9k_blocks" -> m9kBlocks,
    "fmax_ecp5_mhz" -> fmaxEcp5Mhz.map(Double.box).orNull,
    "critical_path" -> criticalPath.orNull,
    "yosys" -> yosys.orNull,
    "method" -> "tools/estimate/estimate.py"
  )
}

object Estimate {
  val script: Path = Paths.get("tools", "estimate", "estimate.py")

  /** The figures of estimate.py's JSON output (the JVM's own run, or a distributed sweep's job). */
  def of(c: Config): Estimate = {
    def opt[T](k: String, f: String => T) = if (c.hasPath(k)) Some(f(k)) else None
    Estimate(
      c.getInt("les"),
      c.getInt("les_arith"),
      c.getInt("les_logic"),
      c.getInt("registers"),
      c.getInt("mult18x18"),
      c.getInt("memory_bits"),
      c.getInt("m9k_blocks"),
      opt("fmax_ecp5_mhz", c.getDouble),
      opt("critical_path", c.getString),
      opt("yosys", c.getString)
    )
  }

  /** Run the estimator on Verilog held in memory. */
  def run(verilog: String, top: String, fmax: Boolean): Estimate = {
    if (!Files.isRegularFile(script)) throw new InputError(s"$script not found: run from the repository root")
    val dir = Files.createTempDirectory("estimate-")
    try {
      val sv = dir.resolve(s"$top.sv")
      val json = dir.resolve("estimate.json")
      Files.write(sv, verilog.getBytes(StandardCharsets.UTF_8))
      val log = new StringBuilder
      val cmd = Seq("python3", script.toString, "--top", top, "--json", json.toString) ++ (if (fmax) Nil
                                                                                           else
                                                                                             Seq(
                                                                                               "--no-fmax"
                                                                                             )) :+ sv.toString
      val status = cmd.!(ProcessLogger(l => log.append(l).append('\n'), l => log.append(l).append('\n')))
      if (status != 0)
        throw new InputError(
          s"the resource estimate failed (${cmd.mkString(" ")}): ${log.toString.trim.linesIterator.toSeq.lastOption.getOrElse("")}"
        )
      of(ConfigFactory.parseFile(json.toFile))
    } finally {
      Files.list(dir).forEach(f => Files.deleteIfExists(f))
      Files.deleteIfExists(dir)
    }
  }
}
