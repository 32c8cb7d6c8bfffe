package reducerload.sim

import reducerload.arm.{ArmOutputCodes, ArmParams}
import reducerload.graph.SampleCodes

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
