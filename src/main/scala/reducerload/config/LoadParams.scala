package reducerload.config

import reducerload.cordic.CordicParams
import reducerload.fixedpoint.Rounding
import reducerload.load.LoadModel
import reducerload.robot.RobotParams

/**
 * The generator's settings (every configuration key): the robot, what to compute (`model`), the sin/cos unit,
 * the fraction bits of each kind of value and the schedule. The datapath they describe is [[arm]]; every
 * node's format, each output's error bound (input quantization, CORDIC error, constant quantization and every
 * rounding) and the schedule are derived there.
 *
 * @param velocityFracBits
 *   fraction bits of the velocity inputs (rad/s)
 * @param accelerationFracBits
 *   fraction bits of the acceleration inputs (rad/s^2)
 * @param constantFracBits
 *   fraction bits of the folded robot constants m3 l1 l3, m3 l2 l3, ...
 * @param internalFracBits
 *   fraction bits (N·m and friends) of products and sums
 * @param outputFracBits
 *   fraction bits of the load output (N·m)
 * @param productRounding
 *   how products drop to `internalFracBits` (truncate costs no adder)
 * @param multiplierLatency
 *   registers after each multiplier (>= 1; more lets Quartus retime into the DSP)
 * @param memoryDelayMinCycles
 *   pipeline-balancing delays of at least this many cycles use block RAM (M9K) instead of registers; 0 keeps
 *   every delay in registers
 * @param monitor
 *   the reducer life and limit monitor beside the arm datapath (`monitor.*` keys)
 * @param targetError
 *   N·m per output torque (one value: every joint; empty: none); the fraction bits become the fewest that
 *   meet it (see [[reducerload.compiler.TargetFit]])
 * @param schedule
 *   clocks per sample, multiplier budget, CORDIC units (`schedule.*` keys; see
 *   [[reducerload.graph.Schedule]])
 */
final case class LoadParams(
    robot: RobotParams = RobotParams(),
    model: LoadModel = LoadModel.Exact,
    cordic: CordicParams = CordicParams.tableResidual,
    velocityFracBits: Int = 20,
    accelerationFracBits: Int = 20,
    constantFracBits: Int = 24,
    internalFracBits: Int = 20,
    outputFracBits: Int = 20,
    productRounding: Rounding = Rounding.Truncate,
    multiplierLatency: Int = 1,
    memoryDelayMinCycles: Int = 4,
    monitor: MonitorSettings = MonitorSettings(),
    schedule: reducerload.graph.ScheduleRequest = reducerload.graph.ScheduleRequest(),
    targetError: Seq[Double] = Nil
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
  require(
    memoryDelayMinCycles == 0 || (memoryDelayMinCycles >= 3 && memoryDelayMinCycles <= 1024),
    s"datapath.memory-delay-min-cycles must be 0 (registers only) or in 3..1024, got $memoryDelayMinCycles"
  )
  require(
    robot.isPlanar3 || !model.closedForm,
    s"model ${model.name} is the planar arm's joint-3 closed form; robot ${robot.source} needs model rnea"
  )
  targetError.foreach(t =>
    require(!t.isNaN && t > 0 && t < 1e6, s"numeric.target-error must be positive N·m, got $t")
  )
  require(
    !monitor.enabled || !model.closedForm,
    s"monitor.enabled = true needs model rnea (the monitor watches every joint of the arm datapath); model ${model.name} is planar3's joint-3 closed form"
  )
}

object LoadParams {

  /** One CORDIC unit shared by the three angles of the joint-3 closed form: a sample every 3 clocks. */
  private def sharedCordic =
    reducerload.graph.ScheduleRequest(clocksPerSample = Some(3), cordicUnits = Some(1))

  /** Exact model, error well under 1e-4 N·m for the typical arm (SPEC.md). */
  val default: LoadParams = LoadParams()

  /**
   * The paper's equation (6), sized for the paper's accuracy: derived bound <= 1e-3 N·m, with the
   * table-assisted residual CORDIC (22 bits, 1024-entry table, no shift-add stage: the residual rotation
   * starts right after the table) and every delay of 3 clocks or more in block RAM.
   */
  val paper: LoadParams = LoadParams(
    model = LoadModel.PaperEq6,
    cordic = CordicParams(
      angleBits = 22,
      outputBits = 22,
      iterations = 11,
      guardBits = 3,
      angleGuardBits = 4,
      architecture = reducerload.cordic.CordicArchitecture.ResidualRotation,
      tableBits = 10
    ),
    velocityFracBits = 16,
    accelerationFracBits = 16,
    constantFracBits = 19,
    internalFracBits = 16,
    outputFracBits = 16,
    memoryDelayMinCycles = 3
  )

  /**
   * The paper's accuracy (derived bound <= 1e-3 N·m, exact model) in the fewest logic elements: the `paper`
   * preset's arithmetic with one CORDIC unit shared by the three angles, so one sample every 3 clocks (50 M
   * samples/s at 150 MHz, far above any control loop's rate).
   */
  val compact: LoadParams = paper.copy(model = LoadModel.Exact, schedule = sharedCordic)

  /**
   * The default's accuracy (derived bound <= 1e-4 N·m, `numeric.target-error` choosing the fraction bits)
   * with one CORDIC unit and shared multipliers, a sample every 3 clocks (50 M samples/s at 150 MHz): a
   * 24-bit unit whose 2^11-entry table feeds the residual rotation directly.
   */
  val shared: LoadParams = LoadParams(
    cordic =
      CordicParams.tableResidual.copy(angleBits = 24, outputBits = 24, iterations = 12, tableBits = 11),
    targetError = Seq(1e-4),
    schedule = sharedCordic
  )

  /**
   * The end of the trade with the fewest resources: 16-bit table-assisted residual CORDIC, one unit shared by
   * the three angles (one sample every 3 clocks; about 2e-2 N·m).
   */
  val smallest: LoadParams = LoadParams(
    cordic = CordicParams(
      angleBits = 16,
      outputBits = 16,
      iterations = 6,
      guardBits = 3,
      angleGuardBits = 4,
      architecture = reducerload.cordic.CordicArchitecture.ResidualRotation,
      tableBits = 4
    ),
    velocityFracBits = 12,
    accelerationFracBits = 12,
    constantFracBits = 16,
    internalFracBits = 12,
    outputFracBits = 12,
    schedule = sharedCordic
  )

  /** The most accurate: classic 30-bit CORDIC, wide datapath. */
  val accurate: LoadParams = LoadParams(
    cordic =
      CordicParams(angleBits = 30, outputBits = 30, iterations = 30, guardBits = 5, angleGuardBits = 5),
    velocityFracBits = 24,
    accelerationFracBits = 24,
    constantFracBits = 28,
    internalFracBits = 24,
    outputFracBits = 24
  )

  /**
   * The highest clock and load rate within the paper's accuracy (derived bound <= 1e-3 N·m): a 23-bit classic
   * CORDIC, whose short carry chains, with no table ROM and no multiply in the angle path, measured the
   * fastest in the sweep (`classic-b23-n20`); paid for in logic elements.
   */
  val fastest: LoadParams = LoadParams(
    cordic =
      CordicParams(angleBits = 23, outputBits = 23, iterations = 20, guardBits = 3, angleGuardBits = 4),
    velocityFracBits = 17,
    accelerationFracBits = 17,
    constantFracBits = 21,
    internalFracBits = 17,
    outputFracBits = 17
  )

  /**
   * Every joint of an arm (model rnea; `--robot` starts from it): a 28-bit table-assisted residual CORDIC and
   * 24 fraction bits inside, for derived bounds under 1e-3 N·m on the UR5 and the Panda at their declared
   * ranges (where |qd| of every joint at once makes the worst case far above the torques of real motions).
   * Shown on the built-in planar3; `--robot FILE.urdf` swaps the robot.
   */
  val arm: LoadParams = LoadParams(
    model = LoadModel.Rnea,
    cordic = CordicParams(
      angleBits = 28,
      outputBits = 28,
      iterations = 16,
      architecture = reducerload.cordic.CordicArchitecture.ResidualRotation,
      tableBits = 9
    ),
    velocityFracBits = 24,
    accelerationFracBits = 22,
    constantFracBits = 28,
    internalFracBits = 24,
    outputFracBits = 20
  )

  /** The arm presets (every joint; not in the joint-3 preset table or sweep). */
  val armPresets: scala.collection.immutable.ListMap[String, LoadParams] =
    scala.collection.immutable.ListMap("arm" -> arm)

  /** Every preset `--preset` accepts. */
  def allPresets: scala.collection.immutable.ListMap[String, LoadParams] = presets ++ armPresets

  /** The shipped presets, in the order the README and the sweep list them. */
  val presets: scala.collection.immutable.ListMap[String, LoadParams] = scala.collection.immutable.ListMap(
    "default" -> default,
    "paper" -> paper,
    "compact" -> compact,
    "shared" -> shared,
    "smallest" -> smallest,
    "accurate" -> accurate,
    "fastest" -> fastest
  )
}
