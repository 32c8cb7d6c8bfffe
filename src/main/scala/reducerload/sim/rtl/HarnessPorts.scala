package reducerload.sim.rtl

import reducerload.arm.{ArmOutputCodes, ArmParams}
import reducerload.graph.SampleCodes

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
 * How the harness talks to a design: ready/valid input of `inputs` (driven in this order from each sample), a
 * valid output of `outputs` (recorded in this order). `inReady = None` means the design is always ready. A
 * plain list, so a caller can build it from a Chisel bundle's elements.
 */
final case class HarnessPorts(
    inputs: Seq[HarnessPort],
    inValid: String,
    inReady: Option[String],
    outValid: String,
    outputs: Seq[HarnessPort],
    clock: String = "clock",
    reset: String = "reset"
) {
  require(inputs.nonEmpty, "harness ports: at least one input data port is needed")
  require(outputs.nonEmpty, "harness ports: at least one output data port is needed")
  (Seq(inValid, outValid, clock, reset) ++ inReady).foreach { n =>
    require(HarnessPorts.identifier.matches(n), s"harness port '$n' is not a Verilog/C++ identifier")
  }

  /** Every port name the harness touches, in the order of the description. */
  val allNames: Seq[String] =
    Seq(clock, reset, inValid) ++ inReady ++ Seq(outValid) ++ inputs.map(_.name) ++ outputs.map(_.name)
  allNames.groupBy(identity).collectFirst { case (n, ns) if ns.size > 1 => n }.foreach { dup =>
    throw new IllegalArgumentException(s"harness ports: '$dup' is named twice")
  }
}

object HarnessPorts {
  private[sim] val identifier = "[A-Za-z_][A-Za-z0-9_]*".r
}

/**
 * `ArmDatapath`'s ports for the [[VerilatorHarness]], as firtool names its Vecs, and its codes as harness
 * values.
 */
object ArmHarnessPorts {
  def apply(p: ArmParams): HarnessPorts = {
    val joints = p.chain.size
    val n = p.numerics
    def each(name: String, width: Int, signed: Boolean, count: Int = joints) =
      (0 until count).map(j => HarnessPort(s"${name}_$j", width, signed))
    HarnessPorts(
      inputs = each("io_in_bits_q", n.angleBits, signed = false) ++
        each("io_in_bits_qd", n.velocityPortFormat.width, signed = true) ++
        each("io_in_bits_qdd", n.accelerationPortFormat.width, signed = true),
      inValid = "io_in_valid",
      inReady = Some("io_in_ready"), // always high; described so the harness honours it all the same
      outValid = "io_out_valid",
      outputs = each(
        "io_out_bits_tau",
        p.analysis.outputPortFormat.width,
        signed = true,
        count = p.graph.outputs.size
      ) ++
        each("io_out_bits_outOfRange", 1, signed = false)
    )
  }

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
