package reducerload.packaging

import reducerload.regmap.CsrEmitters

import scala.xml.{
  Elem,
  MetaData,
  NamespaceBinding,
  NodeSeq,
  Null,
  PrefixedAttribute,
  PrettyPrinter,
  Text,
  TopScope
}

/**
 * `component.xml`: an IP-XACT component (IEEE 1685-2009, the revision Vivado's IP packager reads and writes)
 * for Vivado IP integrator. Bus interfaces use Xilinx's bus definitions (vendor xilinx.com: `interface` axis
 * and aximm for the streams and the AXI4-Lite slave, `signal` clock, reset and interrupt), so IP integrator
 * connects them as it connects its own IP; the register slave's memory map spans its address bits.
 */
object IpXact {
  import InterfaceKind._

  val namespace = "http://www.spiritconsortium.org/XMLSchema/SPIRIT/1685-2009"
  val vendor = "io.reducerload"
  val library = "reducer_load"

  /** Bus and abstraction definition (`xilinx.com:<library>:<name>:1.0`, `<name>_rtl`), and the slave side. */
  private final case class BusType(library: String, name: String, mode: String)
  private def busType(k: InterfaceKind): Option[BusType] = k match {
    case Clock           => Some(BusType("signal", "clock", "slave"))
    case Reset           => Some(BusType("signal", "reset", "slave"))
    case Interrupt       => Some(BusType("signal", "interrupt", "master"))
    case AxiStreamSlave  => Some(BusType("interface", "axis", "slave"))
    case AxiStreamMaster => Some(BusType("interface", "axis", "master"))
    case AxiLiteSlave    => Some(BusType("interface", "aximm", "slave"))
    case Conduit         => None
    case AvalonStSink | AvalonStSource | AvalonMmSlave =>
      throw new IllegalArgumentException(s"$k: an IP-XACT component is generated for bus = axi")
  }

  /** Xilinx's logical port name for a role. */
  private def logical(k: InterfaceKind, r: Role): String = (k, r) match {
    case (_, Role.Clock)                          => "CLK"
    case (_, Role.Reset)                          => "RST"
    case (_, Role.Irq)                            => "INTERRUPT"
    case (_, Role.AxiLite(ch, s))                 => ch + s
    case (_, Role.Data | Role.Valid | Role.Ready) => "T" + r.name.toUpperCase
    case (kind, role) => throw new IllegalArgumentException(s"$kind: no logical port for $role")
  }

  private def s(label: String, body: NodeSeq, attributes: MetaData = Null): Elem =
    Elem("spirit", label, attributes, TopScope, minimizeEmpty = true, body: _*)
  private def text(label: String, value: Any): Elem = s(label, Text(value.toString))
  private def attributes(pairs: (String, String)*): MetaData =
    pairs.foldRight(Null: MetaData) { case ((k, v), next) => new PrefixedAttribute("spirit", k, v, next) }
  private def vlnv(label: String, lib: String, name: String): Elem =
    s(
      label,
      NodeSeq.Empty,
      attributes("vendor" -> "xilinx.com", "library" -> lib, "name" -> name, "version" -> "1.0")
    )
  private def parameter(name: String, value: String): Elem =
    s("parameter", text("name", name) ++ text("value", value))

  def apply(c: Component, command: String): String = {
    val clock = c.interface(Clock).map(_.name)
    val reset = c.interface(Reset).map(_.name)
    val axiLite = c.interface(AxiLiteSlave)
    val memoryMap = "registers"
    def busInterface(i: Interface, bt: BusType): Elem = {
      val modeBody: NodeSeq =
        if (i.kind == AxiLiteSlave) s("memoryMapRef", NodeSeq.Empty, attributes("memoryMapRef" -> memoryMap))
        else NodeSeq.Empty
      val parameters: Seq[Elem] = i.kind match {
        case Clock =>
          val buses = c.interfaces.filter(j => busType(j.kind).exists(_.library == "interface")).map(_.name)
          Seq(parameter("ASSOCIATED_BUSIF", buses.mkString(":"))) ++ reset.map(
            parameter("ASSOCIATED_RESET", _)
          )
        case Reset        => Seq(parameter("POLARITY", "ACTIVE_HIGH"))
        case Interrupt    => Seq(parameter("SENSITIVITY", "LEVEL_HIGH"))
        case AxiLiteSlave => Seq(parameter("PROTOCOL", "AXI4LITE"))
        case _            => Nil
      }
      s(
        "busInterface",
        text("name", i.name) ++ vlnv("busType", bt.library, bt.name) ++
          vlnv("abstractionType", bt.library, bt.name + "_rtl") ++ s(bt.mode, modeBody) ++
          s(
            "portMaps",
            i.ports.map { case (role, p) =>
              s(
                "portMap",
                s("logicalPort", text("name", logical(i.kind, role))) ++ s(
                  "physicalPort",
                  text("name", p.name)
                )
              )
            }
          ) ++ (if (parameters.isEmpty) NodeSeq.Empty else s("parameters", parameters))
      )
    }
    val buses = c.interfaces.flatMap(i => busType(i.kind).map(busInterface(i, _)))
    val memoryMaps = axiLite.toSeq.map { i =>
      val bytes = BigInt(1) << i.port(Role.AxiLite("AW", "ADDR")).get.width
      s(
        "memoryMap",
        text("name", memoryMap) ++ s(
          "addressBlock",
          text("name", "registers") ++ text("baseAddress", 0) ++ text("range", bytes) ++ text("width", 32) ++
            text("usage", "register")
        )
      )
    }
    val fileSet = "sources"
    val views = Seq("synthesis", "simulation").map { v =>
      s(
        "view",
        text("name", s"xilinx_anylanguage$v") ++ text("envIdentifier", s":vivado.xilinx.com:$v") ++
          text("language", "SystemVerilog") ++ text("modelName", c.top) ++
          s("fileSetRef", text("localName", fileSet))
      )
    }
    val ports = c.interfaces.flatMap(_.ports.map(_._2)).map { p =>
      val direction = p.direction match {
        case PortDirection.In  => "in"
        case PortDirection.Out => "out"
      }
      val vector =
        if (p.width == 1) NodeSeq.Empty else s("vector", text("left", p.width - 1) ++ text("right", 0))
      s("port", text("name", p.name) ++ s("wire", text("direction", direction) ++ vector))
    }
    val files = s(
      "fileSet",
      text("name", fileSet) ++ c.sources.map(f =>
        s("file", text("name", f) ++ text("fileType", "systemVerilogSource"))
      )
    )
    val component = Elem(
      "spirit",
      "component",
      Null,
      NamespaceBinding("spirit", namespace, TopScope),
      minimizeEmpty = true,
      text("vendor", vendor) ++ text("library", library) ++ text("name", c.top) ++ text(
        "version",
        c.version
      ) ++
        s("busInterfaces", buses) ++ (if (memoryMaps.isEmpty) NodeSeq.Empty
                                      else s("memoryMaps", memoryMaps)) ++
        s("model", s("views", views) ++ s("ports", ports)) ++ s("fileSets", files) ++
        text("description", c.description): _*
    )
    // Wide enough that no element breaks: a broken empty element would hold whitespace the schema refuses.
    val body = new PrettyPrinter(200, 2, minimizeEmpty = true).format(component)
    // A comment cannot hold the command's "--": it follows in a processing instruction.
    require(!command.contains("?>"), s"command $command: cannot be written in XML")
    val Seq(generated, _) = CsrEmitters.generatedBy(command)
    s"""<?xml version="1.0" encoding="UTF-8"?>
       |<!-- $generated the command in the next line. -->
       |<?regenerate $command?>
       |$body
       |""".stripMargin
  }
}
