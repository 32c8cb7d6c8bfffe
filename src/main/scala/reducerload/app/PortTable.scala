package reducerload.app

import chisel3.Data
import reducerload.sim.rtl.{ModulePort, ModulePorts, PortDirection}

/** One port of an emitted module with what the report says of it. */
final case class PortRow(name: String, direction: String, text: String)

/**
 * The report's port table of a module: rows named from its IO Bundle ([[ModulePorts]]), so no port name is
 * written by hand, and [[complete]] refuses a table that misses a port or names one the module lacks.
 */
final class PortTable(moduleName: String, ports: ModulePorts) {
  private def row(port: ModulePort, text: String) =
    PortRow(port.name, if (port.direction == PortDirection.In) "in" else "out", text)

  /** The row of the port `leaf` (an element of the module's IO Bundle). */
  def apply(leaf: Data, text: String): PortRow = row(ports(leaf), text)

  /** The implicit clock and reset, as every module here has them. */
  def clockAndReset: Seq[PortRow] = Seq(
    row(ports.clock, "1 bit"),
    row(ports.reset, "1 bit, synchronous, active high: clears every valid bit")
  )

  /** `described`, checked to name every port of the module once. */
  def complete(described: Seq[PortRow]): Seq[PortRow] = {
    require(
      described.map(_.name).sorted == ports.all.map(_.name).sorted,
      s"$moduleName: the report describes ports ${described.map(_.name).mkString(", ")}, " +
        s"the module has ${ports.all.map(_.name).mkString(", ")}"
    )
    described
  }

  /** The .sv header's lines, the name padded to `nameWidth`. */
  def lines(rows: Seq[PortRow], nameWidth: Int): Seq[String] =
    "Ports:" +: rows.map(r => s"  ${r.name.padTo(nameWidth, ' ')} ${r.direction.padTo(3, ' ')} ${r.text}")

  /** The report's markdown rows. */
  def markdown(rows: Seq[PortRow]): Seq[String] =
    rows.map(r => s"| `${r.name}` | ${r.direction} | ${r.text} |")
}
