package reducerload.config

import reducerload.fixedpoint.Rounding
import reducerload.graph.Reassociation

/**
 * The arithmetic of the datapath (`datapath.*` keys): the fraction bits of each kind of value, how products
 * round, and how values are delayed. The arm datapath ([[reducerload.arm.ArmParams]]) takes these as they
 * are; the target-error fit moves the fraction bits.
 *
 * @param velocityFracBits
 *   fraction bits of the velocity inputs (rad/s)
 * @param accelerationFracBits
 *   fraction bits of the acceleration inputs (rad/s^2)
 * @param constantFracBits
 *   fraction bits of the folded robot constants
 * @param internalFracBits
 *   fraction bits (N·m and friends) of products and sums
 * @param outputFracBits
 *   fraction bits of the torque outputs (N·m)
 * @param productRounding
 *   how products drop to `internalFracBits` (truncate costs no adder)
 * @param multiplierLatency
 *   registers after each multiplier (>= 1; more lets Quartus retime into the DSP)
 * @param memoryDelayMinCycles
 *   values held at least this many cycles wait in block RAM (M9K) instead of registers
 *   ([[reducerload.graph.HeldTaps]] at 2 clocks per sample or more); 0 keeps every delay in registers
 * @param registeredRoutes
 *   registers storage at 2 clocks per sample or more: every route from a value's register to a shared
 *   multiplier passes registers ([[reducerload.graph.Schedule.routeStages]] more clocks per multiply), so
 *   that the design routes and clocks on a full device (design.md, "Registered routes"). None (`auto`): above
 *   [[reducerload.graph.Schedule.directMaxClocks]] clocks per sample, whichever the device fit chooses.
 *   Wherever routes are registered the CORDIC table's block RAM also gets a register in logic
 *   ([[reducerload.cordic.CordicParams.tableRouteRegister]], set by the schedule: Some(true) at any interval
 *   and storage, None above `directMaxClocks` in either storage)
 * @param reassociate
 *   whether sums of several terms are rebuilt as trees, the earliest terms first, and with `SumsAndProducts`
 *   products too, and the constants on the critical path pushed into the sums they scale
 *   ([[reducerload.graph.Reassociate]]): a shorter critical path; the same values, their formats and bounds
 *   derived anew
 * @param composeParallelAxes
 *   whether RNEA crosses each run of consecutive parallel axes in one rotation by the summed angle
 *   ([[reducerload.dynamics.Rnea.parallelRuns]]): fewer multiply levels on the critical path for a few more
 *   products and sin/cos pairs
 */
final case class DatapathParams(
    velocityFracBits: Int = 20,
    accelerationFracBits: Int = 20,
    constantFracBits: Int = 24,
    internalFracBits: Int = 20,
    outputFracBits: Int = 20,
    productRounding: Rounding = Rounding.Truncate,
    multiplierLatency: Int = 1,
    memoryDelayMinCycles: Int = 4,
    registeredRoutes: Option[Boolean] = None,
    reassociate: Reassociation = Reassociation.Off,
    composeParallelAxes: Boolean = false
) {
  reducerload.graph.Numerics.checkFracBits(
    velocityFracBits,
    accelerationFracBits,
    constantFracBits,
    internalFracBits,
    outputFracBits
  )
  require(
    multiplierLatency >= 1 && multiplierLatency <= 4,
    s"datapath.multiplier-latency must be in 1..4, got $multiplierLatency"
  )
  // A block-RAM delay (pipeline.MemoryDelay) takes 3 cycles or more; 1024 bounds its address counter.
  require(
    memoryDelayMinCycles == 0 || (memoryDelayMinCycles >= 3 && memoryDelayMinCycles <= 1024),
    s"datapath.memory-delay-min-cycles must be 0 (registers only) or in 3..1024, got $memoryDelayMinCycles"
  )

  /** Every kind's fraction bits moved by `d` (the target-error fit's first step). */
  def shifted(d: Int): DatapathParams = copy(
    velocityFracBits = velocityFracBits + d,
    accelerationFracBits = accelerationFracBits + d,
    constantFracBits = constantFracBits + d,
    internalFracBits = internalFracBits + d,
    outputFracBits = outputFracBits + d
  )

}
