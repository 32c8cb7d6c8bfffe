package reducerload.sim

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
