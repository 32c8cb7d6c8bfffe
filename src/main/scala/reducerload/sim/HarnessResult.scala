package reducerload.sim

/**
 * Every valid output of a harness run (values in the order of `HarnessPorts.outputs`) with the cycle it
 * appeared in, and the cycle each input sample was taken (valid && ready) in, counted from the first clock
 * after reset.
 */
final case class HarnessResult(
    outputs: IndexedSeq[IndexedSeq[BigInt]],
    outputCycles: IndexedSeq[Long],
    acceptedCycles: IndexedSeq[Long],
    stats: HarnessStats
)
