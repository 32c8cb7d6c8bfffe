package reducerload.packaging

import chisel3.RawModule
import reducerload.config.BusKind
import reducerload.regmap.{CsrFile, GeneratorVersion}

/**
 * The integration files of an emitted top: for `bus = avalon` a Platform Designer component (`<top>_hw.tcl`),
 * for `bus = axi` an IP-XACT component for Vivado (`component.xml`). Both name `<top>.sv` beside them and
 * describe the interfaces read from the elaborated module, so they cannot disagree with it.
 */
object Packaging {

  /**
   * Elaborate `gen` once for both its Verilog (`emit`, e.g. `ChiselStage.emitSystemVerilog`) and [[files]]:
   * the module `emit` elaborated, which its port names and widths are read from after elaboration.
   */
  def elaborate[M <: RawModule](emit: (=> RawModule) => String)(gen: => M): (M, String) = {
    var elaborated: Option[M] = None
    val verilog = emit { val m = gen; elaborated = Some(m); m }
    (
      elaborated.getOrElse(throw new IllegalStateException("the emitter did not elaborate the module")),
      verilog
    )
  }

  /** The component of `module` (elaborated; its Verilog in `<top>.sv`). */
  def component(module: RawModule, bus: BusKind, description: String): Component = {
    val top = module.name
    Component(top, GeneratorVersion.text, description, Interfaces(module, bus), Seq(s"$top.sv"))
  }

  /** The file for `bus`'s integration tool, headed by `command` (the regeneration command). */
  def files(module: RawModule, bus: BusKind, description: String, command: String): Seq[CsrFile] = {
    lazy val c = component(module, bus, description)
    bus match {
      case BusKind.Avalon => Seq(CsrFile(s"${c.top}_hw.tcl", PlatformDesigner(c, command)))
      case BusKind.Axi    => Seq(CsrFile("component.xml", IpXact(c, command)))
      case BusKind.Bare   => Nil
    }
  }
}
