package reducerload.sim

/**
 * A [[ReplayDesign]]'s replay in primitive arrays (what `run simulate` runs when the design offers it): codes
 * and outputs as longs in the harness ports' order, one [[ArrayReplay.Worker]] of work arrays per thread, no
 * allocation per sample. It writes the same lines as the design's `encode` / `evaluate` / `result`
 * (SimulateEnginesSpec, ReplayArraysSpec).
 */
trait ArrayReplay {

  /** Codes per sample, in the order of the harness's input ports. */
  def inputCount: Int

  /** Values per sample, in the order of the harness's output ports. */
  def outputCount: Int
  def worker(): ArrayReplay.Worker
}

object ArrayReplay {
  trait Worker {

    /** The codes of the row at `rows(row ..)` (values in the design's column order) to `codes(at ..)`. */
    def encode(rows: Array[Double], row: Int, codes: Array[Long], at: Int): Unit

    /** The bit-accurate model of the codes at `codes(at ..)`, to `out(outAt ..)`. */
    def evaluate(codes: Array[Long], at: Int, out: Array[Long], outAt: Int): Unit

    /** [[ReplayDesign.result]] of the row at `rows(row ..)` and the outputs at `out(outAt ..)`. */
    def result(
        index: Long,
        rows: Array[Double],
        row: Int,
        out: Array[Long],
        outAt: Int,
        text: java.lang.StringBuilder,
        errors: Array[Double]
    ): Boolean
  }
}
