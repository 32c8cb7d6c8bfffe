package reducerload.regmap

import chisel3._
import chisel3.util._
import reducerload.arm.{ArmParams, JointSample, PayloadedArm}
import reducerload.monitor.MonitorParams
import reducerload.pipeline.MultiplierImpl

/** One field of a stream beat: bits `lsb` to `lsb + width - 1`; `signed`: a two's complement code. */
final case class StreamField(name: String, lsb: Int, width: Int, signed: Boolean) {
  def msb: Int = lsb + width - 1
}

/**
 * The bit layouts of the sample streams, one sample per beat, fields from bit 0 up in this order. In: `q_j1`
 * .. `q_jn` (unsigned binary angles), `qd_j1` .. `qd_jn`, `qdd_j1` .. `qdd_jn` (two's complement, the port
 * formats of the report). Out: `tau_j1` .. `tau_jn` (two's complement, the torque port format), one
 * out-of-range flag per joint `oor_j1` .. `oor_jn`, and with run-time parameters the 8-bit payload `sequence`
 * the sample was computed with. The hardware and the tests read the layout from here.
 */
object StreamLayout {
  private def place(fields: Seq[(String, Int, Boolean)]): Seq[StreamField] =
    fields
      .foldLeft((Vector.empty[StreamField], 0)) { case ((done, lsb), (n, w, s)) =>
        (done :+ StreamField(n, lsb, w, s), lsb + w)
      }
      ._1

  def input(p: ArmParams): Seq[StreamField] = {
    val n = p.numerics
    val js = 0 until p.chain.size
    place(
      js.map(j => (s"q_j${j + 1}", n.angleBits, false)) ++
        js.map(j => (s"qd_j${j + 1}", n.velocityPortFormat.width, true)) ++
        js.map(j => (s"qdd_j${j + 1}", n.accelerationPortFormat.width, true))
    )
  }

  def output(p: ArmParams): Seq[StreamField] = {
    val js = 0 until p.chain.size
    place(
      js.map(j => (s"tau_j${j + 1}", p.analysis.outputPortFormat.width, true)) ++
        js.map(j => (s"oor_j${j + 1}", 1, false)) ++
        Option.when(p.numerics.parameters.nonEmpty)(("sequence", PayloadedArm.sequenceBits, false)).toSeq
    )
  }

  def width(fields: Seq[StreamField]): Int = fields.map(_.width).sum

  /** A beat of `values` (codes, negative for negative signed ones), in the fields' order. */
  def pack(fields: Seq[StreamField], values: Seq[BigInt]): BigInt = {
    require(values.size == fields.size, s"StreamLayout: ${fields.size} fields, ${values.size} values")
    fields.zip(values).map { case (f, v) => (v & ((BigInt(1) << f.width) - 1)) << f.lsb }.sum
  }

  /** The codes of a beat, signed fields sign-extended. */
  def unpack(fields: Seq[StreamField], beat: BigInt): Seq[BigInt] = fields.map { f =>
    val raw = (beat >> f.lsb) & ((BigInt(1) << f.width) - 1)
    if (f.signed && raw.testBit(f.width - 1)) raw - (BigInt(1) << f.width) else raw
  }
}

/** An Avalon-ST sink: `data`, `valid` in, `ready` out (ready latency 0). */
class AvalonStreamSink(width: Int) extends Bundle {
  val data = Input(UInt(width.W))
  val valid = Input(Bool())
  val ready = Output(Bool())
}

/** An Avalon-ST source: `data`, `valid` out, `ready` in (ready latency 0). */
class AvalonStreamSource(width: Int) extends Bundle {
  val data = Output(UInt(width.W))
  val valid = Output(Bool())
  val ready = Input(Bool())
}

/** An interrupt sender: a level, high while an unmasked event is pending. */
class InterruptSender extends Bundle {
  val irq = Output(Bool())
}

/** An AXI4-Stream slave: `tdata` (a multiple of 8 bits), `tvalid` in, `tready` out. */
class AxiStreamSlave(width: Int) extends Bundle {
  val tdata = Input(UInt(width.W))
  val tvalid = Input(Bool())
  val tready = Output(Bool())
}

/** An AXI4-Stream master: `tdata`, `tvalid` out, `tready` in. */
class AxiStreamMaster(width: Int) extends Bundle {
  val tdata = Output(UInt(width.W))
  val tvalid = Output(Bool())
  val tready = Input(Bool())
}

/** The beat layouts in hardware: a stream beat into the core's sample, the core's output into a beat. */
private object StreamHw {
  def sample(p: ArmParams, beat: UInt, into: JointSample): Unit = {
    val fields = StreamLayout.input(p).map(f => f.name -> f).toMap
    def bits(name: String) = { val f = fields(name); beat(f.msb, f.lsb) }
    (0 until p.chain.size).foreach { j =>
      into.q(j) := bits(s"q_j${j + 1}")
      into.qd(j) := bits(s"qd_j${j + 1}").asSInt
      into.qdd(j) := bits(s"qdd_j${j + 1}").asSInt
    }
  }

  def beat(p: ArmParams, out: CoreOutput): UInt = {
    val parts = StreamLayout.output(p).map { f =>
      val j = f.name.dropWhile(_ != 'j').drop(1)
      if (f.name.startsWith("tau_")) out.torques.tau(j.toInt - 1).asUInt
      else if (f.name.startsWith("oor_")) out.torques.outOfRange(j.toInt - 1).asUInt
      else out.sequence.get
    }
    Cat(parts.reverse)
  }
}

/**
 * The `reducer_load` wrapper for Platform Designer: Avalon-ST sink `in_*` (one sample per beat,
 * [[StreamLayout.input]]), Avalon-ST source `out_*` ([[StreamLayout.output]], honours back-pressure),
 * Avalon-MM slave `csr_*` ([[AvalonSlave]], the map's word addresses), interrupt sender `irq_irq`. Signal
 * names are `<interface>_<role>`, as Platform Designer names them.
 */
class ReducerLoadAvalon(
    val p: ArmParams,
    val monitor: Option[MonitorParams],
    val map: CsrMap,
    topName: String
)(implicit
    multiplierImpl: MultiplierImpl
) extends Module {
  override def desiredName = topName
  val in = IO(new AvalonStreamSink(StreamLayout.width(StreamLayout.input(p))))
  val out = IO(new AvalonStreamSource(StreamLayout.width(StreamLayout.output(p))))
  val csr = IO(new AvalonSlave(map.addressBits))
  val irq = IO(new InterruptSender)

  private val core = Module(new ReducerLoadCore(p, monitor, map))
  core.io.in.valid := in.valid
  in.ready := core.io.in.ready
  StreamHw.sample(p, in.data, core.io.in.bits)
  out.valid := core.io.out.valid
  out.data := StreamHw.beat(p, core.io.out.bits)
  core.io.out.ready := out.ready
  core.io.csr <> csr
  irq.irq := core.io.irq
}

/**
 * The `reducer_load` wrapper for Vivado: AXI4-Stream slave `in_*` and master `out_*` (the Avalon beat
 * layouts, `tdata` zero-padded to a multiple of 8 bits), AXI4-Lite slave `csr_*` ([[AxiLiteSlave]], byte
 * addresses) through [[AxiLiteBridge]] onto the one decoder, interrupt `irq_irq`.
 */
class ReducerLoadAxi(val p: ArmParams, val monitor: Option[MonitorParams], val map: CsrMap, topName: String)(
    implicit multiplierImpl: MultiplierImpl
) extends Module {
  override def desiredName = topName
  private def bytes(w: Int) = (w + 7) / 8 * 8
  val in = IO(new AxiStreamSlave(bytes(StreamLayout.width(StreamLayout.input(p)))))
  val out = IO(new AxiStreamMaster(bytes(StreamLayout.width(StreamLayout.output(p)))))
  val csr = IO(new AxiLiteSlave(map.addressBits + 2))
  val irq = IO(new InterruptSender)

  private val core = Module(new ReducerLoadCore(p, monitor, map))
  core.io.in.valid := in.tvalid
  in.tready := core.io.in.ready
  StreamHw.sample(p, in.tdata, core.io.in.bits)
  out.tvalid := core.io.out.valid
  out.tdata := StreamHw.beat(p, core.io.out.bits).pad(out.tdata.getWidth)
  core.io.out.ready := out.tready
  private val bridge = Module(new AxiLiteBridge(map.addressBits))
  bridge.io.axi <> csr
  core.io.csr <> bridge.io.avalon
  irq.irq := core.io.irq
}

/** A port of the wrapper: its Verilog name, direction ("in" or "out") and width. */
final case class WrapperPort(name: String, direction: String, width: Int)

/**
 * The wrapper's ports named from its interface Bundles as the Verilog names them (`<interface>_<field>`), for
 * the report and the packaging: the one list, no name written by hand.
 */
object WrapperPorts {
  import chisel3.experimental.requireIsChiselType
  import chisel3.reflect.DataMirror

  private def flatten(prefix: String, d: Data, flipped: Boolean): Seq[WrapperPort] = {
    val dir = DataMirror.specifiedDirectionOf(d)
    val f = dir match {
      case SpecifiedDirection.Flip   => !flipped
      case SpecifiedDirection.Input  => true
      case SpecifiedDirection.Output => false
      case _                         => flipped
    }
    d match {
      case b: Record =>
        b.elements.toSeq.reverse.flatMap { case (n, e) => flatten(s"${prefix}_$n", e, f) }
      case leaf =>
        val input = dir match {
          case SpecifiedDirection.Input  => !flipped
          case SpecifiedDirection.Output => flipped
          case SpecifiedDirection.Flip   => !flipped
          case _                         => flipped
        }
        Seq(WrapperPort(prefix, if (input) "in" else "out", leaf.getWidth))
    }
  }

  /** Clock, reset, then each interface's signals in Bundle order. */
  def of(interfaces: Seq[(String, Data)]): Seq[WrapperPort] = {
    interfaces.foreach { case (_, d) => requireIsChiselType(d) }
    Seq(WrapperPort("clock", "in", 1), WrapperPort("reset", "in", 1)) ++
      interfaces.flatMap { case (n, d) => flatten(n, d, flipped = false) }
  }

  def avalon(p: ArmParams, map: CsrMap): Seq[WrapperPort] = of(
    Seq(
      "in" -> new AvalonStreamSink(StreamLayout.width(StreamLayout.input(p))),
      "out" -> new AvalonStreamSource(StreamLayout.width(StreamLayout.output(p))),
      "csr" -> new AvalonSlave(map.addressBits),
      "irq" -> new InterruptSender
    )
  )

  def axi(p: ArmParams, map: CsrMap): Seq[WrapperPort] = of(
    Seq(
      "in" -> new AxiStreamSlave((StreamLayout.width(StreamLayout.input(p)) + 7) / 8 * 8),
      "out" -> new AxiStreamMaster((StreamLayout.width(StreamLayout.output(p)) + 7) / 8 * 8),
      "csr" -> new AxiLiteSlave(map.addressBits + 2),
      "irq" -> new InterruptSender
    )
  )
}
