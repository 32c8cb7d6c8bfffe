package reducerload.packaging

import chisel3.RawModule
import circt.stage.ChiselStage
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.app.Emit
import reducerload.config.BusKind
import reducerload.regmap.{ReducerLoadAvalon, ReducerLoadAxi, RegMapDesign}
import reducerload.testutil.Scratch
import reducerload.testutil.SimBackend.multiplierImpl

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path, Paths}
import java.util.zip.ZipFile
import javax.xml.XMLConstants
import javax.xml.transform.stream.StreamSource
import javax.xml.validation.SchemaFactory
import scala.jdk.CollectionConverters._
import scala.sys.process._
import scala.util.Try

/** A port as the test reads it from the emitted Verilog (not from the packaging's own description). */
final case class VerilogPort(name: String, input: Boolean, width: Int)

/** The designs the test packages, each elaborated once with its Verilog. */
object PackagingDesign {
  private def emit(gen: => RawModule): (RawModule, String) =
    Packaging.elaborate(g =>
      Emit.withBlackBoxes(ChiselStage.emitSystemVerilog(g, Array.empty[String], Emit.firtoolOpts))
    )(gen)
  private def c = RegMapDesign.compiled
  lazy val avalon: (RawModule, String) = emit(
    new ReducerLoadAvalon(c.arm, c.monitor, RegMapDesign.map, "reducer_load")
  )
  lazy val axi: (RawModule, String) = emit(
    new ReducerLoadAxi(c.arm, c.monitor, RegMapDesign.map, "reducer_load")
  )

  /**
   * The top module's ports from its header in the Verilog: firtool writes one port per line, `input` or
   * `output`, an optional `[msb:0]`, the name; a line with the name alone repeats the previous line's
   * direction and width.
   */
  def ports(verilog: String, top: String): Seq[VerilogPort] = {
    val lines = verilog.linesIterator.toIndexedSeq
    val start = lines.indexWhere(_.startsWith(s"module $top("))
    require(start >= 0, s"module $top not in the Verilog")
    val header = lines.drop(start + 1).takeWhile(!_.startsWith(");"))
    val full = """\s*(input|output)\s+(?:\[(\d+):0\]\s+)?([A-Za-z_][A-Za-z0-9_]*),?(?:\s*//.*)?""".r
    val repeated = """\s*([A-Za-z_][A-Za-z0-9_]*),?(?:\s*//.*)?""".r
    header
      .filterNot(_.trim.startsWith("//"))
      .foldLeft(Vector.empty[VerilogPort]) { (done, l) =>
        l match {
          case full(dir, msb, name) =>
            done :+ VerilogPort(name, dir == "input", Option(msb).fold(1)(_.toInt + 1))
          case repeated(name) => done :+ done.last.copy(name = name)
          case other          => throw new IllegalArgumentException(s"unexpected port line '$other'")
        }
      }
  }
}

/** What a `_hw.tcl` declared, as the stub commands recorded it (tools/packaging/qsys_stub.tcl). */
final case class Declared(lines: Seq[Seq[String]]) {
  def all(command: String): Seq[Seq[String]] = lines.filter(_.head == command).map(_.tail)
  def moduleProperty(name: String): Option[String] = all("set_module_property").collectFirst {
    case Seq(`name`, v) => v
  }
  def interfaces: Map[String, (String, String)] =
    all("add_interface").map(a => a(0) -> (a(1), a(2))).toMap
  def property(interface: String, name: String): Option[String] =
    all("set_interface_property").collectFirst { case Seq(`interface`, `name`, v) => v }

  /** (interface, port, role, direction, width) */
  def ports: Seq[(String, String, String, String, Int)] =
    all("add_interface_port").map(a => (a(0), a(1), a(2), a(3), a(4).toInt))
}

/** The checks of a `_hw.tcl` against the Verilog; each returns the problems found (none: it passes). */
object HwTclCheck {

  /** Signal roles per interface type and the properties the test knows (Avalon Interface Specifications). */
  private val roles: Map[String, Set[String]] = Map(
    "clock" -> Set("clk"),
    "reset" -> Set("reset", "reset_n"),
    "avalon_streaming" -> Set("data", "valid", "ready"),
    "avalon" -> Set(
      "address",
      "read",
      "write",
      "writedata",
      "readdata",
      "readdatavalid",
      "waitrequest",
      "byteenable"
    ),
    "interrupt" -> Set("irq")
  )
  private val properties: Map[String, Set[String]] = Map(
    "clock" -> Set("clockRate"),
    "reset" -> Set("associatedClock", "synchronousEdges"),
    "avalon_streaming" -> Set(
      "associatedClock",
      "associatedReset",
      "dataBitsPerSymbol",
      "readyLatency",
      "maxChannel",
      "errorDescriptor"
    ),
    "avalon" -> Set(
      "associatedClock",
      "associatedReset",
      "addressUnits",
      "readLatency",
      "maximumPendingReadTransactions",
      "readWaitTime",
      "writeWaitTime",
      "setupTime",
      "holdTime"
    ),
    "interrupt" -> Set("associatedClock", "associatedReset", "associatedAddressablePoint"),
    "conduit" -> Set("associatedClock", "associatedReset")
  )

  def apply(d: Declared, verilog: Seq[VerilogPort], top: String): Seq[String] = {
    val problems = Seq.newBuilder[String]
    def check(ok: Boolean, what: => String): Unit = if (!ok) problems += what
    check(d.all("package") == Seq(Seq("qsys", "16.1")), s"package require: ${d.all("package")}")
    check(d.moduleProperty("NAME").contains(top), s"module NAME ${d.moduleProperty("NAME")}, not $top")
    Seq("QUARTUS_SYNTH", "SIM_VERILOG").foreach { fs =>
      check(d.all("add_fileset").exists(_.head == fs), s"no fileset $fs")
      check(
        d.all("set_fileset_property").contains(Seq(fs, "TOP_LEVEL", top)),
        s"fileset $fs: TOP_LEVEL is not $top"
      )
      check(
        d.all("add_fileset_file")
          .filter(a => a(0) == s"$top.sv")
          .exists(a => a(1) == "SYSTEM_VERILOG" && a(2) == "PATH"),
        s"fileset $fs: $top.sv is not a SYSTEM_VERILOG file"
      )
    }
    val interfaces = d.interfaces
    // Every Verilog port in exactly one interface, with its direction and width; no other port.
    val declared = d.ports.groupBy(_._2)
    verilog.foreach { p =>
      declared.getOrElse(p.name, Nil) match {
        case Seq((_, _, _, dir, width)) =>
          check(dir == (if (p.input) "Input" else "Output"), s"${p.name}: declared $dir")
          check(width == p.width, s"${p.name}: declared $width bits, the Verilog has ${p.width}")
        case Seq() => problems += s"${p.name}: in no interface"
        case more  => problems += s"${p.name}: in ${more.size} interfaces"
      }
    }
    val names = verilog.map(_.name).toSet
    d.ports.filterNot(p => names(p._2)).foreach(p => problems += s"${p._2}: not a port of $top")
    d.ports.foreach { case (i, port, role, dir, width) =>
      interfaces.get(i) match {
        case None => problems += s"$port: interface $i is not declared"
        case Some((kind, direction)) =>
          roles.get(kind).foreach(r => check(r(role), s"$port: role $role in a $kind interface"))
          if (kind == "avalon_streaming" && role == "data") {
            check(
              d.property(i, "dataBitsPerSymbol").contains(width.toString),
              s"$i: dataBitsPerSymbol is not $width"
            )
            val sink = direction == "end"
            check((dir == "Input") == sink, s"$i: data is $dir on a ${if (sink) "sink" else "source"}")
          }
      }
    }
    interfaces.foreach { case (i, (kind, _)) =>
      check(d.ports.exists(_._1 == i), s"interface $i has no port")
      check(properties.contains(kind), s"interface $i: type $kind")
      d.all("set_interface_property").filter(_.head == i).foreach { case Seq(_, property, value) =>
        check(properties.getOrElse(kind, Set.empty)(property), s"interface $i: property $property for $kind")
        val expected = property match {
          case "associatedClock"            => Some("clock")
          case "associatedReset"            => Some("reset")
          case "associatedAddressablePoint" => Some("avalon")
          case _                            => None
        }
        expected
          .foreach(k => check(interfaces.get(value).exists(_._1 == k), s"interface $i: $property $value"))
      }
      if (kind != "clock")
        check(d.property(i, "associatedClock").isDefined, s"interface $i: no associatedClock")
    }
    problems.result()
  }
}

/** Three one-word streams: a sink, a source, a valid-only source. */
class PackagingStreams extends chisel3.Module {
  import chisel3._
  import chisel3.util.{Decoupled, Valid}
  val io = IO(new Bundle {
    val in = Flipped(Decoupled(UInt(24.W)))
    val out = Decoupled(UInt(40.W))
    val flags = Valid(UInt(3.W))
  })
  io.out.valid := io.in.valid
  io.out.bits := io.in.bits
  io.in.ready := io.out.ready
  io.flags.valid := false.B
  io.flags.bits := 0.U
}

/** Interfaces as separate top-level ports (no `io` Bundle): each port one interface. */
class PackagingTopLevelPorts extends chisel3.Module {
  import chisel3._
  import chisel3.util.Decoupled
  val in = IO(Flipped(Decoupled(UInt(16.W))))
  val csr = IO(new reducerload.regmap.AvalonSlave(4))
  val irq = IO(Output(Bool()))
  in.ready := true.B
  csr.readdata := in.bits
  csr.readdatavalid := RegNext(csr.read, false.B)
  irq := in.valid && csr.write && csr.address.orR && csr.writedata.orR
}

class PackagingSpec extends AnyFlatSpec {
  behavior of "the packaging"

  private val root = Paths.get(sys.env.getOrElse("REDUCERLOAD_CWD", "."))
  private def text(p: Path) = new String(Files.readAllBytes(p), StandardCharsets.UTF_8)

  private def runStub(hwTcl: String): (Int, Declared, String) = {
    val d = Scratch.dir("packaging-tcl-")
    val f = d.resolve("component_hw.tcl")
    Files.write(f, hwTcl.getBytes(StandardCharsets.UTF_8))
    val out = Seq.newBuilder[String]
    val err = new StringBuilder
    val status = Seq("tclsh", root.resolve("tools/packaging/qsys_stub.tcl").toString, f.toString)
      .!(ProcessLogger(out += _, l => err.append(l).append('\n')))
    (status, Declared(out.result().map(_.split("\t", -1).toSeq)), err.toString)
  }
  private def tclsh: Boolean = Try(
    Seq("tclsh").#<(new java.io.ByteArrayInputStream(Array.emptyByteArray)).!
  ).isSuccess

  it should "read the interfaces from the IO Bundles: streams, the Avalon slave, interrupt, clock, reset" in {
    val (m, verilog) = PackagingDesign.avalon
    val is = Interfaces(m, BusKind.Avalon)
    println(
      s"PackagingSpec: ${m.name}: " + is
        .map(i => s"${i.name} ${i.kind} (${i.ports.size} ports)")
        .mkString(", ")
    )
    assert(
      is.map(i => i.name -> i.kind) == Seq(
        "clock" -> InterfaceKind.Clock,
        "reset" -> InterfaceKind.Reset,
        "in" -> InterfaceKind.AvalonStSink,
        "out" -> InterfaceKind.AvalonStSource,
        "csr" -> InterfaceKind.AvalonMmSlave,
        "irq" -> InterfaceKind.Interrupt
      )
    )
    val csr = is.find(_.name == "csr").get
    assert(
      csr.port(Role.Address).contains(Port("csr_address", PortDirection.In, RegMapDesign.map.addressBits))
    )
    assert(csr.port(Role.ReadDataValid).map(_.direction).contains(PortDirection.Out))
    // Every Verilog port once, under the name firtool gave it.
    val ports = PackagingDesign.ports(verilog, m.name)
    assert(
      is.flatMap(_.ports.map(_._2)).map(p => (p.name, p.direction == PortDirection.In, p.width)).sorted ==
        ports.map(p => (p.name, p.input, p.width)).sorted
    )
  }

  it should "classify a one-word ready/valid stream as Avalon-ST or AXI4-Stream by the bus setting" in {
    var m: Option[PackagingStreams] = None
    ChiselStage.emitCHIRRTL({ val s = new PackagingStreams; m = Some(s); s })
    val kinds = (b: BusKind) => Interfaces(m.get, b).map(i => i.name -> i.kind).toMap
    assert(kinds(BusKind.Avalon)("in") == InterfaceKind.AvalonStSink)
    assert(kinds(BusKind.Avalon)("out") == InterfaceKind.AvalonStSource)
    assert(kinds(BusKind.Axi)("in") == InterfaceKind.AxiStreamSlave)
    assert(kinds(BusKind.Axi)("out") == InterfaceKind.AxiStreamMaster)
    val flags = Interfaces(m.get, BusKind.Avalon).find(_.name == "flags").get
    assert(flags.kind == InterfaceKind.AvalonStSource && flags.port(Role.Ready).isEmpty)
    assert(
      Interfaces(m.get, BusKind.Avalon)
        .find(_.name == "in")
        .get
        .port(Role.Data)
        .contains(
          Port("io_in_bits", PortDirection.In, 24)
        )
    )
  }

  it should "take a top-level port that is an interface whole, and name its ports as Chisel does" in {
    var m: Option[PackagingTopLevelPorts] = None
    ChiselStage.emitCHIRRTL({ val t = new PackagingTopLevelPorts; m = Some(t); t })
    val is = Interfaces(m.get, BusKind.Avalon)
    assert(
      is.map(i => i.name -> i.kind) == Seq(
        "clock" -> InterfaceKind.Clock,
        "reset" -> InterfaceKind.Reset,
        "in" -> InterfaceKind.AvalonStSink,
        "csr" -> InterfaceKind.AvalonMmSlave,
        "irq" -> InterfaceKind.Interrupt
      )
    )
    assert(is.find(_.name == "csr").get.port(Role.Address).contains(Port("csr_address", PortDirection.In, 4)))
    assert(is.find(_.name == "in").get.port(Role.Ready).contains(Port("in_ready", PortDirection.Out, 1)))
  }

  it should "give a _hw.tcl that runs under tclsh with stub commands and declares every port once, as the Verilog has it" in {
    assume(tclsh, "tclsh is not installed (apt-get install tcl)")
    val (m, verilog) = PackagingDesign.avalon
    val hw = Packaging.files(m, BusKind.Avalon, "test component", "./sbt \"run emit --test\"")
    assert(hw.map(_.name) == Seq(s"${m.name}_hw.tcl"))
    val tcl = hw.head.text
    assert(tcl.startsWith("# Generated by the reducer-load generator"))
    assert(tcl.linesIterator.toSeq(1) == "#   ./sbt \"run emit --test\"")
    val (status, declared, err) = runStub(tcl)
    assert(status == 0, err)
    val ports = PackagingDesign.ports(verilog, m.name)
    val problems = HwTclCheck(declared, ports, m.name)
    println(
      s"PackagingSpec: ${m.name}_hw.tcl: ${declared.interfaces.size} interfaces, ${declared.ports.size} ports " +
        s"(Verilog: ${ports.size}), ${problems.size} problems"
    )
    assert(problems.isEmpty, problems.mkString("\n"))
    assert(declared.interfaces("csr") == ("avalon", "end"))
    assert(declared.property("csr", "addressUnits").contains("WORDS"))
    assert(declared.property("irq", "associatedAddressablePoint").contains("csr"))
    assert(declared.property("reset", "synchronousEdges").contains("BOTH"))
  }

  it should "find a _hw.tcl that disagrees with the Verilog (a width, a lost port, a port twice, an unknown role)" in {
    assume(tclsh, "tclsh is not installed (apt-get install tcl)")
    val (m, verilog) = PackagingDesign.avalon
    val tcl = Packaging.files(m, BusKind.Avalon, "test", "test").head.text
    val ports = PackagingDesign.ports(verilog, m.name)
    def problems(t: String) = {
      val (status, d, err) = runStub(t)
      assert(status == 0, err)
      HwTclCheck(d, ports, m.name)
    }
    val irqLine = tcl.linesIterator.find(_.startsWith("add_interface_port irq ")).get
    val widened = tcl.replace(irqLine, irqLine.replaceAll(" 1$", " 2"))
    assert(problems(widened).exists(_.contains("irq_irq: declared 2 bits")))
    assert(problems(tcl.replace(irqLine + "\n", "")).exists(_.contains("irq_irq: in no interface")))
    assert(problems(tcl.replace(irqLine, irqLine + "\n" + irqLine)).exists(_.contains("in 2 interfaces")))
    assert(
      problems(tcl.replace(irqLine, irqLine.replace(" irq Output", " interrupt Output"))).exists(
        _.contains("role interrupt")
      )
    )
    // A command Platform Designer does not have fails under the stubs.
    assert(runStub(tcl + "add_interface_prot irq irq_irq irq Output 1\n")._1 != 0)
  }

  /**
   * The IEEE 1685-2009 schema from the pinned wheel (tools/packaging/requirements.txt); None: unreachable.
   */
  private lazy val schema: Option[Path] = {
    val cache = Paths.get(sys.props("user.home"), ".cache", "reducer-load-ipxact")
    val requirements = root.resolve("tools/packaging/requirements.txt")
    def wheel = Option(cache.toFile.listFiles()).toSeq.flatten.find(_.getName.endsWith(".whl"))
    if (wheel.isEmpty) {
      Files.createDirectories(cache)
      val cmd = Seq(
        "python3",
        "-m",
        "pip",
        "download",
        "-q",
        "--no-deps",
        "--require-hashes",
        "-r",
        requirements.toString,
        "-d",
        cache.toString
      )
      val log = new StringBuilder
      val status = cmd.!(ProcessLogger(l => log.append(l).append('\n'), l => log.append(l).append('\n')))
      if (status != 0) println(s"PackagingSpec: ${cmd.mkString(" ")} failed:\n$log")
    }
    wheel.map { w =>
      val d = Scratch.dir("ipxact-schema-")
      val zip = new ZipFile(w)
      try
        zip
          .entries()
          .asScala
          .filter(_.getName.matches("pyEDAA/IPXACT/Schema/ieee-1685-2009/[^/]+\\.xsd"))
          .foreach { e =>
            Files.copy(zip.getInputStream(e), d.resolve(e.getName.split('/').last))
          }
      finally zip.close()
      d.resolve("index.xsd")
    }
  }

  private def validate(xml: String): Option[String] = {
    val factory = SchemaFactory.newInstance(XMLConstants.W3C_XML_SCHEMA_NS_URI)
    // Local files only: the schema includes its parts by relative path, and nothing may be fetched.
    factory.setProperty(XMLConstants.ACCESS_EXTERNAL_SCHEMA, "file")
    val validator = factory.newSchema(schema.get.toFile).newValidator()
    validator.setProperty(XMLConstants.ACCESS_EXTERNAL_DTD, "")
    Try(validator.validate(new StreamSource(new java.io.StringReader(xml)))).failed.toOption.map(_.getMessage)
  }

  it should "give an IP-XACT component.xml valid against the IEEE 1685-2009 schema, whose ports are the Verilog's" in {
    assume(
      schema.isDefined,
      "the IP-XACT schema could not be fetched (pip download of tools/packaging/requirements.txt)"
    )
    val (m, verilog) = PackagingDesign.axi
    val files = Packaging.files(m, BusKind.Axi, "test component", "./sbt \"run emit --bus axi\"")
    assert(files.map(_.name) == Seq("component.xml"))
    val xml = files.head.text
    assert(xml.linesIterator.toSeq(2) == "<?regenerate ./sbt \"run emit --bus axi\"?>")
    val refused = validate(xml)
    assert(refused.isEmpty, refused.getOrElse(""))
    val doc = scala.xml.XML.loadString(xml)
    val ports = (doc \\ "port").map { p =>
      val vector = p \\ "vector"
      VerilogPort(
        (p \ "name").text,
        (p \\ "direction").text == "in",
        if (vector.isEmpty) 1 else (vector \ "left").text.toInt - (vector \ "right").text.toInt + 1
      )
    }
    val expected = PackagingDesign.ports(verilog, m.name)
    assert(ports.sortBy(_.name) == expected.sortBy(_.name))
    val buses = (doc \\ "busInterface").map { b =>
      (b \ "name").text -> (
        (b \ "busType" \@ "{http://www.spiritconsortium.org/XMLSchema/SPIRIT/1685-2009}name"),
        (b \\ "portMap").map(pm => (pm \ "logicalPort" \ "name").text -> (pm \ "physicalPort" \ "name").text)
      )
    }.toMap
    println(
      s"PackagingSpec: component.xml: " + buses
        .map { case (n, (t, pm)) => s"$n $t (${pm.size})" }
        .mkString(", ")
    )
    val mapped = buses.values.flatMap(_._2.map(_._2)).toSeq
    assert(mapped.distinct.size == mapped.size, "a port in two bus interfaces")
    assert(mapped.forall(expected.map(_.name).toSet), "a port map names no port")
    val csr = buses("csr")
    assert(csr._1 == "aximm")
    // AMBA AXI4-Lite's signals without the optional AWPROT and ARPROT.
    val axiLite = "AWADDR AWVALID AWREADY WDATA WSTRB WVALID WREADY BRESP BVALID BREADY " +
      "ARADDR ARVALID ARREADY RDATA RRESP RVALID RREADY"
    assert(csr._2.map(_._1).sorted == axiLite.split(' ').toSeq.sorted)
    assert(buses("irq") == ("interrupt", Seq("INTERRUPT" -> "irq_irq")))
    // The wrapper's sample streams are AXI4-Stream interfaces, not loose ports.
    Seq("in", "out").foreach(s =>
      assert(
        buses(s)._1 == "axis" && buses(s)._2.map(_._1).sorted == Seq("TDATA", "TREADY", "TVALID"),
        buses(s)
      )
    )
    assert(buses("clock")._2 == Seq("CLK" -> "clock") && buses("reset")._2 == Seq("RST" -> "reset"))
    val range = (doc \\ "addressBlock" \ "range").text.toInt
    assert(range == 4 * RegMapDesign.map.words)
  }

  it should "find a component.xml the schema refuses" in {
    assume(
      schema.isDefined,
      "the IP-XACT schema could not be fetched (pip download of tools/packaging/requirements.txt)"
    )
    val (m, _) = PackagingDesign.axi
    val xml = Packaging.files(m, BusKind.Axi, "test", "test").head.text
    // Elements out of the schema's order, and a direction the schema does not know.
    assert(
      validate(
        xml.replaceFirst("(<spirit:version>[^<]*</spirit:version>)", "$1<spirit:version>2</spirit:version>")
      ).isDefined
    )
    assert(
      validate(
        xml.replaceFirst(
          "<spirit:direction>in</spirit:direction>",
          "<spirit:direction>input</spirit:direction>"
        )
      ).isDefined
    )
  }
}
