package reducerload.config

import reducerload.cordic.CordicParams
import reducerload.fixedpoint.Rounding
import reducerload.load.LoadModel
import reducerload.robot.RobotParams

/**
 * The generator's settings (every configuration key): the robot, what to compute (`model`), the sin/cos unit,
 * the fraction bits of each kind of value and the schedule. Reading them checks each sub-configuration on its
 * own; [[reducerload.compiler.Compiler]] derives the datapath (every node's format, each output's error
 * bound, the schedule).
 *
 * @param payload
 *   the run-time payload's declared set and frame (`payload.*` keys)
 * @param gravity
 *   the gravity vector as run-time inputs, and its declared bound (`gravity.*` keys)
 * @param datapath
 *   fraction bits, product rounding, multiplier latency, block-RAM delays (`datapath.*` keys)
 * @param monitor
 *   the reducer life and limit monitor beside the arm datapath (`monitor.*` keys)
 * @param targetError
 *   N·m per output torque (one value: every joint; empty: none); the fraction bits become the fewest that
 *   meet it (see [[reducerload.compiler.TargetFit]])
 * @param schedule
 *   clocks per sample, multiplier budget, CORDIC units (`schedule.*` keys; see
 *   [[reducerload.graph.Schedule]]; `auto` values are chosen by the device fit)
 * @param device
 *   the target device and its logic headroom (`device.*` keys; see [[reducerload.compiler.DeviceFit]])
 */
final case class LoadParams(
    robot: RobotParams = RobotParams(),
    payload: PayloadSettings = PayloadSettings(),
    gravity: GravitySettings = GravitySettings(),
    model: LoadModel = LoadModel.Exact,
    cordic: CordicParams = CordicParams.tableResidual,
    datapath: DatapathParams = DatapathParams(),
    monitor: MonitorSettings = MonitorSettings(),
    schedule: reducerload.graph.ScheduleRequest = reducerload.graph.ScheduleRequest(),
    targetError: Seq[Double] = Nil,
    device: DeviceTarget = DeviceTarget(),
    bus: BusSettings = BusSettings()
) {

  require(
    robot.isPlanar3 || !model.closedForm,
    s"model ${model.name} is the planar arm's joint-3 closed form; robot ${robot.source} needs model rnea"
  )
  require(
    robot.mounting.isFloor || !model.closedForm,
    s"${reducerload.robot.Mounting.setting} = ${robot.mounting} needs model rnea (the joint-3 closed form ${model.name} assumes planar3's own gravity)"
  )
  require(
    !payload.enabled || !model.closedForm,
    s"payload.enabled = true needs model rnea; model ${model.name} is planar3's joint-3 closed form"
  )
  require(
    !payload.enabled || !robot.isPlanar3,
    "payload.enabled = true needs a URDF robot (robot.source): the built-in planar3 has no link to carry it"
  )
  require(
    !gravity.runtime || !model.closedForm,
    s"gravity.runtime = true needs model rnea; model ${model.name} is planar3's joint-3 closed form"
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

  /** The exact joint-3 load of the built-in planar3, derived bound under 1e-4 N·m. */
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
    datapath = DatapathParams(
      velocityFracBits = 16,
      accelerationFracBits = 16,
      constantFracBits = 19,
      internalFracBits = 16,
      outputFracBits = 16,
      memoryDelayMinCycles = 3
    )
  )

  /**
   * The paper's accuracy (derived bound <= 1e-3 N·m, exact model) in the fewest logic elements: the `paper`
   * preset's arithmetic with one CORDIC unit shared by the three angles, so one sample every 3 clocks (still
   * far above any control loop's rate).
   */
  val compact: LoadParams = paper.copy(model = LoadModel.Exact, schedule = sharedCordic)

  /**
   * The default's accuracy (derived bound <= 1e-4 N·m, `numeric.target-error` choosing the fraction bits)
   * with one CORDIC unit and shared multipliers, a sample every 3 clocks: a 24-bit unit whose 2^11-entry
   * table feeds the residual rotation directly.
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
    datapath = DatapathParams(
      velocityFracBits = 12,
      accelerationFracBits = 12,
      constantFracBits = 16,
      internalFracBits = 12,
      outputFracBits = 12
    ),
    schedule = sharedCordic
  )

  /** The most accurate: classic 30-bit CORDIC, wide datapath. */
  val accurate: LoadParams = LoadParams(
    cordic =
      CordicParams(angleBits = 30, outputBits = 30, iterations = 30, guardBits = 5, angleGuardBits = 5),
    datapath = DatapathParams(
      velocityFracBits = 24,
      accelerationFracBits = 24,
      constantFracBits = 28,
      internalFracBits = 24,
      outputFracBits = 24
    )
  )

  /**
   * The highest clock and load rate within the paper's accuracy (derived bound <= 1e-3 N·m): a 23-bit classic
   * CORDIC: short carry chains, no table ROM and no multiply in the angle path (docs/sweep has the figures);
   * paid for in logic elements.
   */
  val fastest: LoadParams = LoadParams(
    cordic =
      CordicParams(angleBits = 23, outputBits = 23, iterations = 20, guardBits = 3, angleGuardBits = 4),
    datapath = DatapathParams(
      velocityFracBits = 17,
      accelerationFracBits = 17,
      constantFracBits = 21,
      internalFracBits = 17,
      outputFracBits = 17
    )
  )

  /**
   * Every joint of an arm (model rnea; `--robot` starts from it): a 28-bit table-assisted residual CORDIC and
   * 24 fraction bits inside, for derived bounds under 1e-3 N·m on the UR5 and the Panda at their declared
   * ranges (where |qd| of every joint at once makes the worst case far above the torques of real motions).
   * Sums rebuilt as trees: the same derived bounds and a shorter critical path (the UR5's device fit 23 -> 22
   * clocks per sample, 190 -> 163 cycles; docs/design.md). The joint-3 presets keep the written sums, which
   * their measured figures (docs/benchmarks.md) are of. Shown on the built-in planar3; `--robot FILE.urdf`
   * swaps the robot.
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
    datapath = DatapathParams(
      velocityFracBits = 24,
      accelerationFracBits = 22,
      constantFracBits = 28,
      internalFracBits = 24,
      outputFracBits = 20,
      reassociate = reducerload.graph.Reassociation.Sums
    )
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
