package reducerload.packaging

import reducerload.config.BusKind
import chisel3._
import chisel3.reflect.DataMirror

/** A port's direction, seen from the component. */
sealed abstract class PortDirection
object PortDirection {
  case object In extends PortDirection
  case object Out extends PortDirection
}

/** One Verilog port of the emitted top: its name as Chisel emits it, direction and width in bits. */
final case class Port(name: String, direction: PortDirection, width: Int)

/**
 * What a port does in its interface, in the bus's own vocabulary; each emitter spells it its tool's way
 * (Platform Designer roles are lower case, Xilinx logical ports upper case).
 */
sealed abstract class Role(val name: String)
object Role {
  case object Clock extends Role("clk")
  case object Reset extends Role("reset")
  case object Irq extends Role("irq")

  /** A stream's payload, handshake. */
  case object Data extends Role("data")
  case object Valid extends Role("valid")
  case object Ready extends Role("ready")

  /** An Avalon-MM slave's signals (Avalon Interface Specifications, memory-mapped signal roles). */
  sealed abstract class Avalon(name: String) extends Role(name)
  case object Address extends Avalon("address")
  case object Read extends Avalon("read")
  case object Write extends Avalon("write")
  case object WriteData extends Avalon("writedata")
  case object ReadData extends Avalon("readdata")
  case object ReadDataValid extends Avalon("readdatavalid")
  case object WaitRequest extends Avalon("waitrequest")
  case object ByteEnable extends Avalon("byteenable")
  val avalon: Seq[Avalon] =
    Seq(Address, Read, Write, WriteData, ReadData, ReadDataValid, WaitRequest, ByteEnable)

  /** An AXI4-Lite signal: channel and signal, as AMBA names them (`AW` + `ADDR` = `AWADDR`). */
  final case class AxiLite(channel: String, signal: String) extends Role(channel + signal)

  /** A conduit's signal: any name (its path inside the interface's Bundle). */
  final case class Conduit(path: String) extends Role(path)
}

/** What an interface is. Streams and the interrupt name the side the component takes. */
sealed trait InterfaceKind
object InterfaceKind {
  case object Clock extends InterfaceKind
  case object Reset extends InterfaceKind
  case object AvalonStSink extends InterfaceKind
  case object AvalonStSource extends InterfaceKind
  case object AvalonMmSlave extends InterfaceKind
  case object AxiStreamSlave extends InterfaceKind
  case object AxiStreamMaster extends InterfaceKind
  case object AxiLiteSlave extends InterfaceKind
  case object Interrupt extends InterfaceKind

  /** Signals that follow no standard protocol: exported as they are. */
  case object Conduit extends InterfaceKind
}

/** One interface of the component: its name (the IO field's), kind and ports with their roles. */
final case class Interface(name: String, kind: InterfaceKind, ports: Seq[(Role, Port)]) {
  def port(role: Role): Option[Port] = ports.collectFirst { case (`role`, p) => p }
}

/**
 * The interfaces of an elaborated module, read from its IO Bundles: the port names are the ones Chisel gives
 * the Verilog ports ([[DataMirror.fullModulePorts]]), so a renamed field renames the packaging too. Each IO
 * field is one interface, classified by its shape ([[Interfaces.classify]]), not by its Scala class, so any
 * Bundle of the same fields packages the same way.
 */
object Interfaces {

  /** The clock, the reset, then the other ports' interfaces, in declaration order. */
  def apply(module: RawModule, bus: BusKind): Seq[Interface] = {
    val names: Map[Data, String] = DataMirror.fullModulePorts(module).map { case (n, d) => d -> n }.toMap
    def port(d: Data): Port = {
      val direction = DataMirror.directionOf(d) match {
        case ActualDirection.Input  => PortDirection.In
        case ActualDirection.Output => PortDirection.Out
        case other =>
          throw new IllegalArgumentException(s"port ${names(d)}: direction $other cannot be packaged")
      }
      Port(names(d), direction, d.getWidth)
    }
    val ports = new Ports(names, port)
    // A Bundle's `elements` lists its fields last-declared first; the Verilog has them in declaration order.
    DataMirror.modulePorts(module).flatMap {
      case (name, c: Clock) => Seq(Interface(name, InterfaceKind.Clock, Seq(Role.Clock -> port(c))))
      case ("reset", r)     => Seq(Interface("reset", InterfaceKind.Reset, Seq(Role.Reset -> port(r))))
      // A port that is one interface (`val csr = IO(...)`), or a Bundle of them (`io`): one per field.
      case (name, r: Record) =>
        val whole = classify(name, r, bus, ports)
        if (whole.kind != InterfaceKind.Conduit) Seq(whole)
        else r.elements.toSeq.reverse.map { case (field, d) => classify(field, d, bus, ports) }
      case (name, d) => Seq(classify(name, d, bus, ports))
    }
  }

  /** Leaves and ports of one module; `port` knows the Verilog names. */
  final class Ports(val name: Data => String, val port: Data => Port) {
    def leaves(d: Data): Seq[Data] = d match {
      case a: Aggregate => a.getElements.flatMap(leaves)
      case e            => Seq(e)
    }
  }

  /** The interface a port Bundle field is, by its shape: see the cases. */
  def classify(name: String, d: Data, bus: BusKind, ports: Ports): Interface = {
    import ports.port
    def fields(r: Record): Set[String] = r.elements.keySet.toSet
    def in(d: Data): Boolean = DataMirror.directionOf(d) == ActualDirection.Input
    d match {
      // A ready/valid (or valid-only) stream of one word: an Avalon-ST or AXI4-Stream endpoint.
      case r: Record if stream(r).isDefined =>
        val (valid, payload, ready) = stream(r).get
        val kind = (bus, in(valid)) match {
          case (BusKind.Avalon, true)  => InterfaceKind.AvalonStSink
          case (BusKind.Avalon, false) => InterfaceKind.AvalonStSource
          case (BusKind.Axi, true)     => InterfaceKind.AxiStreamSlave
          case (BusKind.Axi, false)    => InterfaceKind.AxiStreamMaster
          case (BusKind.Bare, _) =>
            throw new IllegalArgumentException(
              s"$name: a stream is Avalon-ST or AXI4-Stream; bus = none has neither"
            )
        }
        Interface(
          name,
          kind,
          Seq(Role.Data -> port(payload), Role.Valid -> port(valid)) ++ ready.map(rd =>
            Role.Ready -> port(rd)
          )
        )
      // An Avalon-MM slave: the spec's signal names as fields, the address an input.
      case r: Record
          if fields(r).contains("address") && in(r.elements("address")) &&
            fields(r).subsetOf(Role.avalon.map(_.name).toSet) =>
        Interface(
          name,
          InterfaceKind.AvalonMmSlave,
          Role.avalon.flatMap(role => r.elements.get(role.name).map(f => role -> port(f)))
        )
      // An AXI4-Lite slave: five Decoupled channels aw, w, b, ar, r.
      case r: Record if fields(r) == Set("aw", "w", "b", "ar", "r") =>
        Interface(name, InterfaceKind.AxiLiteSlave, axiLite(r, port))
      // One output bit named as an interrupt.
      case b: Bool if !in(b) && Set("irq", "interrupt").contains(name) =>
        Interface(name, InterfaceKind.Interrupt, Seq(Role.Irq -> port(b)))
      case _ =>
        Interface(
          name,
          InterfaceKind.Conduit,
          ports.leaves(d).map { leaf =>
            val p = port(leaf)
            Role.Conduit(p.name.stripPrefix(ports.name(d)).stripPrefix("_") match {
              case "" => name
              case s  => s
            }) -> p
          }
        )
    }
  }

  /**
   * `valid`, a one-word payload (`bits` or `data`) and optionally `ready`, or the same under AXI4-Stream's
   * names (`tvalid`, `tdata`, `tready`): a stream endpoint's valid, payload and ready.
   */
  private def stream(r: Record): Option[(Data, Data, Option[Data])] = {
    val f = r.elements
    Seq(("valid", Seq("bits", "data"), "ready"), ("tvalid", Seq("tdata"), "tready")).flatMap {
      case (valid, payloads, ready) =>
        for {
          v <- f.get(valid).filter(_.isInstanceOf[Bool])
          name <- payloads.find(f.contains)
          payload <- f.get(name).filter(_.isInstanceOf[Element])
          if f.keySet == Set(valid, name) ++ f.keySet.intersect(Set(ready))
        } yield (v, payload, f.get(ready))
    }.headOption
  }

  /** The channels' handshakes and payloads under their AMBA names; a Bundle payload's fields by name. */
  private def axiLite(r: Record, port: Data => Port): Seq[(Role, Port)] =
    Seq("aw" -> "AW", "w" -> "W", "b" -> "B", "ar" -> "AR", "r" -> "R").flatMap { case (field, channel) =>
      val c = r.elements(field).asInstanceOf[Record]
      val payload: Seq[(String, Data)] = c.elements("bits") match {
        case b: Record => b.elements.toSeq.reverse.map { case (n, d) => n.toUpperCase -> d }
        case e =>
          val signal = channel match {
            case "AW" | "AR" => "ADDR"
            case "B"         => "RESP"
            case other => throw new IllegalArgumentException(s"AXI4-Lite channel $other: a one-field payload")
          }
          Seq(signal -> e)
      }
      (payload ++ Seq("VALID" -> c.elements("valid"), "READY" -> c.elements("ready"))).map { case (s, d) =>
        Role.AxiLite(channel, s) -> port(d)
      }
    }
}
