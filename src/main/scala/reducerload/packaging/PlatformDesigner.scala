package reducerload.packaging

import reducerload.regmap.CsrEmitters

/**
 * A component for an integration tool: the top module, its interfaces ([[Interfaces]]) and the HDL files that
 * hold it (beside the component file, the first the top's).
 */
final case class Component(
    top: String,
    version: String,
    description: String,
    interfaces: Seq[Interface],
    sources: Seq[String]
) {
  require(sources.nonEmpty, s"component $top: no source file")
  def interface(kind: InterfaceKind): Option[Interface] = interfaces.find(_.kind == kind)
}

/**
 * `<top>_hw.tcl`: a Platform Designer component (Quartus Prime Platform Designer user guide, "Component
 * Interface Tcl Reference"; the interface properties of the Avalon Interface Specifications). The clock and
 * reset are the sinks every other interface is associated with; the streams are Avalon-ST with one symbol per
 * beat and ready latency 0; the register slave addresses words and returns `readdata` with `readdatavalid`
 * one clock after `read` (so at most one read pending); the interrupt is served through that slave.
 */
object PlatformDesigner {
  import InterfaceKind._

  /** `add_interface` type and direction (end: the component receives, start: it drives). */
  private def declaration(k: InterfaceKind): (String, String) = k match {
    case Clock          => ("clock", "end")
    case Reset          => ("reset", "end")
    case AvalonStSink   => ("avalon_streaming", "end")
    case AvalonStSource => ("avalon_streaming", "start")
    case AvalonMmSlave  => ("avalon", "end")
    case Interrupt      => ("interrupt", "end")
    case Conduit        => ("conduit", "end")
    case AxiStreamSlave | AxiStreamMaster | AxiLiteSlave =>
      throw new IllegalArgumentException(s"$k: a Platform Designer component is generated for bus = avalon")
  }

  private def quote(s: String): String = "\"" + s.flatMap {
    case c @ ('"' | '\\' | '$' | '[' | ']') => s"\\$c"
    case c                                  => c.toString
  } + "\""

  def apply(c: Component, command: String): String = {
    val clock = c.interface(Clock).map(_.name)
    val reset = c.interface(Reset).map(_.name)
    val slave = c.interface(AvalonMmSlave).map(_.name)
    val b = new StringBuilder
    def line(s: String = ""): Unit = b.append(s).append('\n')
    CsrEmitters.generatedBy(command).foreach(l => line(s"# $l"))
    line()
    line("package require -exact qsys 16.1")
    line()
    line(s"set_module_property NAME ${c.top}")
    line(s"set_module_property DISPLAY_NAME ${c.top}")
    line(s"set_module_property VERSION ${c.version}")
    line(s"set_module_property DESCRIPTION ${quote(c.description)}")
    line("set_module_property GROUP \"reducer-load\"")
    line("set_module_property AUTHOR \"reducer-load generator\"")
    line("set_module_property INTERNAL false")
    line("set_module_property EDITABLE false")
    line("set_module_property INSTANTIATE_IN_SYSTEM_MODULE true")
    // One HDL file serves synthesis and Verilog simulation alike.
    Seq("QUARTUS_SYNTH", "SIM_VERILOG").foreach { fileset =>
      line()
      line(s"add_fileset $fileset $fileset \"\" \"\"")
      line(s"set_fileset_property $fileset TOP_LEVEL ${c.top}")
      c.sources.zipWithIndex.foreach { case (f, i) =>
        line(s"add_fileset_file $f SYSTEM_VERILOG PATH $f" + (if (i == 0) " TOP_LEVEL_FILE" else ""))
      }
    }
    c.interfaces.foreach { i =>
      val (kind, direction) = declaration(i.kind)
      def property(name: String, value: String): Unit = line(s"set_interface_property ${i.name} $name $value")
      line()
      line(s"add_interface ${i.name} $kind $direction")
      if (i.kind != Clock) clock.foreach(property("associatedClock", _))
      if (i.kind != Clock && i.kind != Reset) reset.foreach(property("associatedReset", _))
      i.kind match {
        case Clock => property("clockRate", "0")
        // Chisel's implicit reset: active high, asserted and released on the clock edge.
        case Reset => property("synchronousEdges", "BOTH")
        case AvalonStSink | AvalonStSource =>
          property("dataBitsPerSymbol", i.port(Role.Data).get.width.toString)
          property("readyLatency", "0")
          property("maxChannel", "0")
          property("errorDescriptor", "\"\"")
        case AvalonMmSlave =>
          property("addressUnits", "WORDS")
          property("readLatency", "0")
          property("maximumPendingReadTransactions", if (i.port(Role.ReadDataValid).isDefined) "1" else "0")
          property("readWaitTime", "0")
          property("writeWaitTime", "0")
          property("setupTime", "0")
          property("holdTime", "0")
        case Interrupt => slave.foreach(property("associatedAddressablePoint", _))
        case _         => ()
      }
      i.ports.foreach { case (role, p) =>
        val dir = p.direction match {
          case PortDirection.In  => "Input"
          case PortDirection.Out => "Output"
        }
        line(s"add_interface_port ${i.name} ${p.name} ${role.name} $dir ${p.width}")
      }
    }
    b.toString
  }
}
