package reducerload.sim

import reducerload.load.{LoadInputCodes, LoadOutputCodes, LoadParams}

/** `LoadDatapath`'s ports for the [[VerilatorHarness]], as firtool names them, and its codes as harness values. */
object LoadHarnessPorts {
  def apply(p: LoadParams): HarnessPorts = {
    val angles = Seq("t1", "t2", "t3").map(n => HarnessPort(s"io_in_bits_$n", p.angleBits, signed = false))
    val velocities = p.velocityFormats.zipWithIndex.map { case (f, i) => HarnessPort(s"io_in_bits_d${i + 1}", f.width, signed = true) }
    val accelerations = p.accelerationFormats.zipWithIndex.map { case (f, i) => HarnessPort(s"io_in_bits_dd${i + 1}", f.width, signed = true) }
    HarnessPorts(
      inputs = angles ++ velocities ++ accelerations,
      inValid = "io_in_valid",
      inReady = Some("io_in_ready"),
      outValid = "io_out_valid",
      outputs = Seq(HarnessPort("io_out_bits_load", p.outputFormat.width, signed = true), HarnessPort("io_out_bits_outOfRange", 1, signed = false))
    )
  }

  /** Input values in the order of [[apply]]'s `inputs`. */
  def values(in: LoadInputCodes): Seq[BigInt] = Seq(in.t1, in.t2, in.t3) ++ in.d ++ in.dd

  def codes(out: IndexedSeq[BigInt]): LoadOutputCodes = {
    require(out.size == 2, s"LoadDatapath harness output has ${out.size} values, expected load and outOfRange")
    LoadOutputCodes(out(0), out(1) != 0)
  }
}
