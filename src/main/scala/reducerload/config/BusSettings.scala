package reducerload.config

/** Which bus the `reducer_load` wrapper speaks. */
sealed abstract class BusKind(val name: String)
object BusKind {

  /** Avalon-ST sample streams, Avalon-MM registers (Platform Designer). */
  case object Avalon extends BusKind("avalon")

  /** AXI4-Stream sample streams, AXI4-Lite registers (Vivado IP integrator). */
  case object Axi extends BusKind("axi")

  /** No wrapper: the datapath or the monitored arm as the top, ports as before. */
  case object Bare extends BusKind("none")
  val all: Seq[BusKind] = Seq(Avalon, Axi, Bare)
}

/**
 * The bus wrapper: its bus (`bus.interface`) and its module name (`bus.top-name`), stable across settings so
 * an instantiation survives every change.
 */
final case class BusSettings(kind: BusKind = BusKind.Avalon, topName: String = BusSettings.defaultTopName) {
  require(
    BusSettings.moduleName.matches(topName),
    s"bus.top-name must be a Verilog identifier (a letter or _, then letters, digits, _), got '$topName'"
  )
}

object BusSettings {
  val defaultTopName = "reducer_load"
  val moduleName = "[A-Za-z_][A-Za-z0-9_]*".r
}
