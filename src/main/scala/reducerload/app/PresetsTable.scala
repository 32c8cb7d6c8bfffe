package reducerload.app

import reducerload.cordic.{CordicArchitecture, CordicParams}
import reducerload.compiler.{Compiled, Compiler}
import reducerload.config.LoadParams

/**
 * The README's preset table, made from the presets themselves: architecture, rate, latency, the derived error
 * bound and the max error measured on the golden traces (bit-accurate model, which the RTL tests prove equal
 * to the hardware). `./sbt --error "run presets-table"` prints it; DocsFreshnessSpec checks the README
 * carries it.
 */
object PresetsTable {

  /** One line for a CORDIC unit: what replaces the first iterations, the shift-add stages, what follows. */
  def cordicSummary(c: CordicParams): String = {
    val table = if (c.tableBits > 0) Seq(s"table 2^${c.tableBits}") else Nil
    val stages = c.iterations - c.firstIteration
    val shiftAdd = if (stages > 0) Seq(s"$stages shift-add stage${if (stages == 1) "" else "s"}") else Nil
    val residual =
      if (c.architecture == CordicArchitecture.ResidualRotation) Seq("residual rotation") else Nil
    val classic = if (c.architecture == CordicArchitecture.Classic && c.tableBits == 0) "classic, " else ""
    classic + (table ++ shiftAdd ++ residual).mkString(" + ") + s", ${c.angleBits} / ${c.outputBits} bits"
  }

  def rate(c: Compiled): String = {
    val ii = c.arm.schedule.clocksPerSample
    if (ii == 1) "every clock" else s"every $ii clocks"
  }

  def header: Seq[String] =
    Seq(
      "preset",
      "model",
      "CORDIC (angle / output bits)",
      "CORDIC units",
      "one sample",
      "latency",
      "derived bound",
      "max error, golden traces"
    )

  def markdown: String = {
    val rows = LoadParams.presets.toSeq.map { case (name, p) =>
      val c = Compiler.compile(p, s"preset $name")
      Seq(
        s"`$name`",
        p.model.name,
        cordicSummary(p.cordic),
        c.arm.schedule.cordicUnits.toString,
        rate(c),
        s"${c.arm.latency} cycles",
        f"${c.arm.errorBound}%.2e N·m",
        f"${Sweep.goldenError(c)}%.2e N·m"
      )
    }
    (header +: header.map(_ => "---") +: rows).map(_.mkString("| ", " | ", " |")).mkString("\n")
  }
}
