package reducerload.regmap

import chisel3._
import chisel3.util._
import reducerload.arm.{ArmParams, JointSample, PayloadedArm}
import reducerload.fixedpoint.FixedFormat
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

  /** The joint (0-based) of each computed torque, in output order (a closed form computes one joint's). */
  def torqueJoints(p: ArmParams): Seq[Int] =
    p.analysis.outputs.map(o => p.chain.joints.indexWhere(_.name == o.name))

  def output(p: ArmParams): Seq[StreamField] = {
    val js = 0 until p.chain.size
    place(
      torqueJoints(p).map(j => (s"tau_j${j + 1}", p.analysis.outputPortFormat.width, true)) ++
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
    if (f.signed) FixedFormat.fromTwosComplement(raw, f.width) else raw
  }
}

/** An Avalon-ST source: `data`, `valid` out, `ready` in (ready latency 0); `Flipped`, the sink. */
class AvalonStream(width: Int) extends Bundle {
  val data = Output(UInt(width.W))
  val valid = Output(Bool())
  val ready = Input(Bool())
}

/** An interrupt sender: a level, high while an unmasked event is pending. */
class InterruptSender extends Bundle {
  val irq = Output(Bool())
}

/** An AXI4-Stream master: `tdata` (a multiple of 8 bits), `tvalid` out, `tready` in; `Flipped`, the slave. */
class AxiStream(width: Int) extends Bundle {
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
    val joints = p.chain.size
    val parts = out.torques.tau.map(_.asUInt) ++ out.torques.outOfRange.map(_.asUInt) ++ out.sequence.toSeq
    require(parts.size == StreamLayout.output(p).size && joints == out.torques.outOfRange.size)
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
  private val faces = new AvalonInterfaces(p, map)
  val in = IO(faces.in)
  val out = IO(faces.out)
  val csr = IO(faces.csr)
  val irq = IO(faces.irq)

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
  private val faces = new AxiInterfaces(p, map)
  val in = IO(faces.in)
  val out = IO(faces.out)
  val csr = IO(faces.csr)
  val irq = IO(faces.irq)

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

/**
 * A wrapper's interfaces, declared once: the module takes its IO from here and [[WrapperPorts]] lists the
 * same Bundles for the report without elaborating. Each call is a fresh Chisel type.
 */
sealed abstract class WrapperInterfaces {
  def in: Data
  def out: Data
  def csr: Data
  def irq: InterruptSender = new InterruptSender
  def all: Seq[(String, Data)] = Seq("in" -> in, "out" -> out, "csr" -> csr, "irq" -> irq)
}

/** Avalon-ST sink and source (one sample per beat), Avalon-MM slave (word addresses), interrupt. */
final class AvalonInterfaces(p: ArmParams, map: CsrMap) extends WrapperInterfaces {
  def in: AvalonStream = Flipped(new AvalonStream(StreamLayout.width(StreamLayout.input(p))))
  def out: AvalonStream = new AvalonStream(StreamLayout.width(StreamLayout.output(p)))
  def csr: AvalonSlave = new AvalonSlave(map.addressBits)
}

/**
 * AXI4-Stream slave and master (`tdata` padded to whole bytes), AXI4-Lite slave (byte addresses), interrupt.
 */
final class AxiInterfaces(p: ArmParams, map: CsrMap) extends WrapperInterfaces {
  private def bytes(w: Int) = (w + 7) / 8 * 8
  def in: AxiStream = Flipped(new AxiStream(bytes(StreamLayout.width(StreamLayout.input(p)))))
  def out: AxiStream = new AxiStream(bytes(StreamLayout.width(StreamLayout.output(p))))
  def csr: AxiLiteSlave = new AxiLiteSlave(map.addressBits + 2)
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

  /**
   * Leaves in Verilog order; a leaf is an input when its nearest Input/Output (which coerces everything below
   * it, default Output) is Input, toggled by every Flipped above that one.
   */
  private def flatten(prefix: String, d: Data, flip: Boolean, coerced: Option[Boolean]): Seq[WrapperPort] = {
    val (f, c) = coerced match {
      case Some(_) => (flip, coerced)
      case None =>
        DataMirror.specifiedDirectionOf(d) match {
          case SpecifiedDirection.Flip   => (!flip, None)
          case SpecifiedDirection.Input  => (flip, Some(true))
          case SpecifiedDirection.Output => (flip, Some(false))
          case _                         => (flip, None)
        }
    }
    d match {
      case b: Record => b.elements.toSeq.reverse.flatMap { case (n, e) => flatten(s"${prefix}_$n", e, f, c) }
      case leaf =>
        Seq(WrapperPort(prefix, if (c.getOrElse(false) ^ f) "in" else "out", leaf.getWidth))
    }
  }

  /** Clock, reset, then each interface's signals in Bundle order. */
  def of(interfaces: Seq[(String, Data)]): Seq[WrapperPort] = {
    interfaces.foreach { case (_, d) => requireIsChiselType(d) }
    Seq(WrapperPort("clock", "in", 1), WrapperPort("reset", "in", 1)) ++
      interfaces.flatMap { case (n, d) => flatten(n, d, flip = false, None) }
  }

  def avalon(p: ArmParams, map: CsrMap): Seq[WrapperPort] = of(new AvalonInterfaces(p, map).all)

  def axi(p: ArmParams, map: CsrMap): Seq[WrapperPort] = of(new AxiInterfaces(p, map).all)
}
