package reducerload.sim.rtl

import chisel3.{Data, Record, SInt}
import chisel3.util.{DecoupledIO, Valid}
import reducerload.arm.{ArmIO, ArmOutputCodes, ArmParams}
import reducerload.graph.SampleCodes
import reducerload.monitor.MonitoredArmIO

/**
 * One data port of a design as the Verilog names it (firtool: `io_in_bits_t1`, `io_in_bits_q_0` for a Vec).
 */
final case class HarnessPort(name: String, width: Int, signed: Boolean) {
  require(HarnessPorts.identifier.matches(name), s"harness port '$name' is not a Verilog/C++ identifier")
  require(
    width >= 1 && width <= 64,
    s"harness port '$name' is $width bits wide: the harness supports 1 to 64 bits"
  )

  val minValue: BigInt = if (signed) -(BigInt(1) << (width - 1)) else BigInt(0)
  val maxValue: BigInt = if (signed) (BigInt(1) << (width - 1)) - 1 else (BigInt(1) << width) - 1
}

/**
 * A monitor's host port ([[reducerload.monitor.MonitorHostPort]]): one-clock `snapshot` and `clear` pulses, a
 * word `readAddress` whose `readData` comes one clock later, and `snapshotDone`. Its inputs are also among
 * [[HarnessPorts.held]]: `run simulate` holds them at 0; a stimulus run ([[CompiledHarness.drive]]) drives
 * them.
 */
final case class HostPorts(
    snapshot: String,
    clear: String,
    readAddress: HarnessPort,
    readData: HarnessPort,
    snapshotDone: String
) {
  Seq(snapshot, clear, snapshotDone).foreach { n =>
    require(HarnessPorts.identifier.matches(n), s"harness port '$n' is not a Verilog/C++ identifier")
  }
  require(
    !readData.signed && readData.width <= 63,
    "harness: the host's read data must be unsigned, < 64 bits"
  )
}

/**
 * How the harness talks to a design: ready/valid input of `inputs` (driven in this order from each sample), a
 * valid output of `outputs` (recorded in this order). `inReady = None` means the design is always ready.
 * `held` inputs (a monitor's host port) are held at 0 by `run simulate`; `host` names a monitor's host port
 * for stimulus runs. [[HarnessPorts.stream]] derives it from the module's IO Bundle.
 */
final case class HarnessPorts(
    inputs: Seq[HarnessPort],
    inValid: String,
    inReady: Option[String],
    outValid: String,
    outputs: Seq[HarnessPort],
    clock: String = "clock",
    reset: String = "reset",
    held: Seq[HarnessPort] = Nil,
    host: Option[HostPorts] = None
) {
  host.foreach { h =>
    Seq(h.snapshot, h.clear, h.readAddress.name).foreach { n =>
      require(held.exists(_.name == n), s"harness ports: host input '$n' is not among the held inputs")
    }
  }
  require(inputs.nonEmpty, "harness ports: at least one input data port is needed")
  require(outputs.nonEmpty, "harness ports: at least one output data port is needed")
  (Seq(inValid, outValid, clock, reset) ++ inReady).foreach { n =>
    require(HarnessPorts.identifier.matches(n), s"harness port '$n' is not a Verilog/C++ identifier")
  }

  /** Every port name the harness touches, in the order of the description. */
  val allNames: Seq[String] =
    Seq(clock, reset, inValid) ++ inReady ++ Seq(outValid) ++ inputs.map(_.name) ++ outputs.map(_.name) ++
      held.map(_.name)
  allNames.groupBy(identity).collectFirst { case (n, ns) if ns.size > 1 => n }.foreach { dup =>
    throw new IllegalArgumentException(s"harness ports: '$dup' is named twice")
  }
}

object HarnessPorts {
  private[sim] val identifier = "[A-Za-z_][A-Za-z0-9_]*".r

  /**
   * The description of a module whose `ports` take samples on `in` and give results on `out`; every other
   * input but clock and reset is held at 0.
   */
  def stream(ports: ModulePorts, in: DecoupledIO[_ <: Data], out: Valid[_ <: Data]): HarnessPorts = {
    val inputs = ports.leaves(in.bits)
    val driven = (Seq(ports.clock, ports.reset, ports(in.valid)) ++ inputs).toSet
    HarnessPorts(
      inputs = inputs.map(_.harness),
      inValid = ports(in.valid).name,
      inReady = Some(ports(in.ready).name),
      outValid = ports(out.valid).name,
      outputs = ports.leaves(out.bits).map(_.harness),
      clock = ports.clock.name,
      reset = ports.reset.name,
      held = ports.all.filter(p => p.direction == PortDirection.In && !driven(p)).map(_.harness)
    )
  }
}

/** Which way a port carries data, seen from the module. */
sealed trait PortDirection
object PortDirection {
  case object In extends PortDirection
  case object Out extends PortDirection
}

/** One port of an emitted module: its Verilog name, direction, width and signedness (SInt). */
final case class ModulePort(name: String, direction: PortDirection, width: Int, signed: Boolean) {
  def harness: HarnessPort = HarnessPort(name, width, signed)
}

/**
 * The ports of a `Module` with implicit clock and reset whose IO is `io`, derived from the IO Bundle (a
 * Chisel type; nothing is elaborated) in the order and with the names firtool gives them: `clock`, `reset`,
 * then each ground field of `io` named by its path (`io_in_bits_q_0`, `io_out_valid`, `io_host_readAddress`).
 * [[apply(leaf*]] finds the port of one field of `io`, so callers name ports by the Bundle's fields.
 */
final class ModulePorts private (val all: Seq[ModulePort], byLeaf: Seq[(Data, ModulePort)]) {
  def clock: ModulePort = all(0)
  def reset: ModulePort = all(1)

  /** The port of `leaf`, a ground field of `io`. */
  def apply(leaf: Data): ModulePort = byLeaf
    .collectFirst { case (d, p) if d eq leaf => p }
    .getOrElse(throw new IllegalArgumentException(s"$leaf is not a ground field of the module's IO"))

  /** The ports of `field`'s ground fields, a field of `io`, in port order. */
  def leaves(field: Data): Seq[ModulePort] = ModulePorts.groundFields(field).map(apply)
}

object ModulePorts {
  def apply(io: Record): ModulePorts = {
    val fields = ground(io, "io", Direction.Unspecified)
    val ports = fields.map { case (d, (name, direction)) =>
      d -> ModulePort(name, direction, d.getWidth, d.isInstanceOf[SInt])
    }
    val clockAndReset = Seq("clock", "reset").map(ModulePort(_, PortDirection.In, 1, signed = false))
    new ModulePorts(clockAndReset ++ ports.map(_._2), ports)
  }

  /** Chisel's specified direction of a field, resolved as `Flipped`, `Input` and `Output` nest. */
  private sealed trait Direction
  private object Direction {
    case object Unspecified extends Direction
    case object Flip extends Direction
    case object In extends Direction
    case object Out extends Direction

    def of(d: Data): Direction = chisel3.reflect.DataMirror.specifiedDirectionOf(d) match {
      case chisel3.SpecifiedDirection.Unspecified => Unspecified
      case chisel3.SpecifiedDirection.Flip        => Flip
      case chisel3.SpecifiedDirection.Input       => In
      case chisel3.SpecifiedDirection.Output      => Out
    }

    /** An `Input` or `Output` aggregate fixes its fields' direction; a flipped one flips theirs. */
    def nest(parent: Direction, child: Direction): Direction = (parent, child) match {
      case (In | Out, _)       => parent
      case (Unspecified, _)    => child
      case (Flip, Unspecified) => Flip
      case (Flip, Flip)        => Unspecified
      case (Flip, In)          => Out
      case (Flip, Out)         => In
    }
  }

  private def groundFields(d: Data): Seq[Data] = ground(d, "", Direction.Unspecified).map(_._1)

  /** `d`'s ground fields with their port names (under `prefix`) and directions, in firtool's port order. */
  private def ground(d: Data, prefix: String, parent: Direction): Seq[(Data, (String, PortDirection))] = {
    val direction = Direction.nest(parent, Direction.of(d))
    def name(part: String) = if (prefix.isEmpty) part else s"${prefix}_$part"
    d match {
      // A Bundle's elements are listed last field first; its ports come in declaration order.
      case r: Record => r.elements.toSeq.reverse.flatMap { case (n, e) => ground(e, name(n), direction) }
      case v: chisel3.Vec[_] => v.indices.flatMap(i => ground(v(i), name(i.toString), direction))
      case _ =>
        val port = direction match {
          case Direction.Unspecified | Direction.Out => PortDirection.Out
          case Direction.Flip | Direction.In         => PortDirection.In
        }
        Seq(d -> (prefix, port))
    }
  }
}

/**
 * `ArmDatapath`'s ports for the [[VerilatorHarness]], as firtool names its Vecs, and its codes as harness
 * values.
 */
object ArmHarnessPorts {

  /**
   * `io`'s ports ([[ArmIO]], or [[MonitoredArmIO]] with its host inputs held at 0 by `run simulate` and
   * driven by a stimulus run) for the harness.
   */
  def apply(io: ArmIO): HarnessPorts = {
    val ports = ModulePorts(io)
    val stream = HarnessPorts.stream(ports, io.in, io.out)
    io match {
      case m: MonitoredArmIO =>
        stream.copy(host =
          Some(
            HostPorts(
              snapshot = ports(m.host.snapshot).name,
              clear = ports(m.host.clear).name,
              readAddress = ports(m.host.readAddress).harness,
              readData = ports(m.host.readData).harness,
              snapshotDone = ports(m.host.snapshotDone).name
            )
          )
        )
      case _ => stream
    }
  }

  /** [[ArmDatapath]]'s ports. */
  def apply(p: ArmParams): HarnessPorts = apply(new ArmIO(p))

  /** Input values in the order of [[apply]]'s `inputs`. */
  def values(in: SampleCodes): Seq[BigInt] = in.angles ++ in.velocities ++ in.accelerations

  /**
   * Output codes from values in the order of [[apply]]'s `outputs`: `torques` torques, then one flag per
   * joint.
   */
  def codes(out: IndexedSeq[BigInt], torques: Int): ArmOutputCodes = {
    require(
      out.size > torques,
      s"ArmDatapath harness output has ${out.size} values for $torques torques and the joints' flags"
    )
    ArmOutputCodes(out.take(torques), out.drop(torques).map(_ != 0))
  }
}

/** A port in a Verilog module header: direction ("input", "output" or "inout") and width in bits. */
final case class VerilogPort(name: String, direction: String, width: Int)

/**
 * The port list of one module in firtool's output, read so the harness can check a port description before a
 * long C++ build (a wrong width would otherwise be masked silently). firtool writes one port per line and
 * leaves out the direction and range when they repeat the previous port's (`input clock,` then `reset,`), so
 * both carry over.
 */
object VerilogPortList {
  private val portLine =
    """^\s*(input|output|inout)?\s*(?:\[(\d+):(\d+)\])?\s*([A-Za-z_][A-Za-z0-9_$]*)\s*,?\s*(?://.*)?$""".r

  def apply(verilog: String, module: String): Seq[VerilogPort] = {
    val start = s"(?m)^\\s*module\\s+${java.util.regex.Pattern.quote(module)}\\s*\\(".r
      .findFirstMatchIn(verilog)
      .getOrElse(throw new IllegalArgumentException(s"the Verilog has no module '$module'"))
    val end = verilog.indexOf(");", start.end)
    require(end > 0, s"module '$module': the port list never ends")
    var direction = ""
    var width = 1
    verilog
      .substring(start.end, end)
      .linesIterator
      .map(_.trim)
      .filter(l => l.nonEmpty && !l.startsWith("//"))
      .map {
        case portLine(dir, hi, lo, name) =>
          if (dir != null) direction = dir
          if (dir != null || hi != null) width = if (hi == null) 1 else math.abs(hi.toInt - lo.toInt) + 1
          require(direction.nonEmpty, s"module '$module': port '$name' has no direction")
          VerilogPort(name, direction, width)
        case other =>
          throw new IllegalArgumentException(
            s"module '$module': cannot read the port line '$other' (one port per line expected, as firtool writes)"
          )
      }
      .toSeq
  }
}
