package reducerload.load

import reducerload.cordic.CordicParams
import reducerload.fixedpoint.{Bounded, FixedFormat, Rounding}

/**
 * Generator parameters of [[LoadDatapath]]. Every format below is derived from the declared ranges
 * in `robot` with [[Bounded]]; nothing is hard-coded. The derived `errorBound` covers input
 * quantization (round to nearest), CORDIC error, constant quantization and every rounding.
 *
 * @param velocityFracBits     fraction bits of the velocity inputs (rad/s)
 * @param accelerationFracBits fraction bits of the acceleration inputs (rad/s^2)
 * @param constantFracBits     fraction bits of the folded robot constants m3 l1 l3, m3 l2 l3, ...
 * @param internalFracBits     fraction bits (N·m and friends) of products and sums
 * @param outputFracBits       fraction bits of the load output (N·m)
 * @param productRounding      how products drop to `internalFracBits` (truncate costs no adder)
 * @param multiplierLatency    registers after each multiplier (>= 1; more lets Quartus retime into the DSP)
 * @param memoryDelayMinCycles pipeline-balancing delays of at least this many cycles use block RAM
 *                             (M9K) instead of registers; 0 keeps every delay in registers
 * @param cordicUnits          3: one CORDIC unit per angle, one sample per clock; 1: one unit
 *                             time-shared by the three angles, one sample every 3 clocks (resource
 *                             sharing for sample rates far below the clock)
 * @param monitor              the reducer life and limit monitor beside the arm datapath (`monitor.*` keys)
 * @param targetError          model rnea: N·m per joint (one value: every joint; empty: none); the fraction bits become
 *                             the fewest that meet it (see [[reducerload.arm.ArmConfig]])
 * @param schedule             model rnea: clocks per sample, multiplier budget, CORDIC units (`schedule.*` keys; see [[reducerload.graph.Schedule]])
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
  cordicUnits: Int = 3,
  monitor: reducerload.monitor.MonitorSettings = reducerload.monitor.MonitorSettings(),
  schedule: reducerload.graph.ScheduleRequest = reducerload.graph.ScheduleRequest(),
  targetError: Seq[Double] = Nil) {

  Seq(
    "velocityFracBits" -> velocityFracBits,
    "accelerationFracBits" -> accelerationFracBits,
    "constantFracBits" -> constantFracBits,
    "internalFracBits" -> internalFracBits,
    "outputFracBits" -> outputFracBits
  ).foreach { case (name, bits) => require(bits >= 1 && bits <= 40, s"LoadParams.$name must be in 1..40, got $bits") }
  require(outputFracBits <= internalFracBits,
    s"LoadParams.outputFracBits ($outputFracBits) must not exceed internalFracBits ($internalFracBits)")
  require(2 * velocityFracBits >= internalFracBits,
    s"LoadParams.internalFracBits ($internalFracBits) must not exceed 2 * velocityFracBits (${2 * velocityFracBits})")
  require(constantFracBits + accelerationFracBits >= internalFracBits,
    s"LoadParams.internalFracBits ($internalFracBits) must not exceed constantFracBits + accelerationFracBits (${constantFracBits + accelerationFracBits})")
  require(constantFracBits + cordic.outputFormat.fracBits >= internalFracBits,
    s"LoadParams.internalFracBits ($internalFracBits) must not exceed constantFracBits + the sin/cos fraction bits (${constantFracBits + cordic.outputFormat.fracBits})")
  require(multiplierLatency >= 1 && multiplierLatency <= 4, s"LoadParams.multiplierLatency must be in 1..4, got $multiplierLatency")
  require(memoryDelayMinCycles == 0 || (memoryDelayMinCycles >= 3 && memoryDelayMinCycles <= 1024),
    s"LoadParams.memoryDelayMinCycles must be 0 (registers only) or in 3..1024, got $memoryDelayMinCycles")

  require(cordicUnits == 1 || cordicUnits == 3,
    s"LoadParams.cordicUnits must be 3 (one CORDIC unit per angle) or 1 (one unit shared by the three angles), got $cordicUnits")

  /** Clocks between samples: the three angles of a sample over the CORDIC units (1, or 3 with one shared unit). */
  require(model.closedForm || cordicUnits == 3,
    s"datapath.cordic-units = $cordicUnits: sharing CORDIC units is for the joint-3 closed forms (models exact, paper); model rnea has one unit per joint angle")
  require(robot.isPlanar3 || !model.closedForm,
    s"model ${model.name} is the planar arm's joint-3 closed form; robot ${robot.source} needs model rnea")

  require(!model.closedForm || schedule == reducerload.graph.ScheduleRequest(),
    s"schedule.* applies to model rnea (every joint of an arm); the joint-3 closed form ${model.name} shares CORDIC units by datapath.cordic-units")

  require(!model.closedForm || targetError.isEmpty,
    s"numeric.target-error applies to model rnea (every joint of an arm); the joint-3 closed form ${model.name} takes its fraction bits as set")
  targetError.foreach(t => require(!t.isNaN && t > 0 && t < 1e6, s"numeric.target-error must be positive N·m, got $t"))

  require(!monitor.enabled || !model.closedForm,
    s"monitor.enabled = true needs model rnea (the monitor watches every joint of the arm datapath); model ${model.name} is planar3's joint-3 closed form")

  lazy val samplePeriod: Int = if (model.closedForm) 3 / cordicUnits else 1

  private lazy val F = internalFracBits
  private lazy val lsbF = math.pow(2.0, -F)

  // ---- inputs ----
  lazy val angleBits: Int = cordic.angleBits
  lazy val velocityFormats: Seq[FixedFormat] = robot.maxVelocity.map(v => FixedFormat.forRange(v, velocityFracBits))
  lazy val accelerationFormats: Seq[FixedFormat] = robot.maxAcceleration.map(a => FixedFormat.forRange(a, accelerationFracBits))

  /** Declared limits as the codes a value at the limit converts to: codes beyond them are clamped and flagged. */
  lazy val velocityLimitRaw: Seq[BigInt] = robot.maxVelocity.zip(velocityFormats).map { case (v, f) => f.quantize(v, Rounding.HalfUp) }
  lazy val accelerationLimitRaw: Seq[BigInt] =
    robot.maxAcceleration.zip(accelerationFormats).map { case (a, f) => f.quantize(a, Rounding.HalfUp) }

  /** Half a code: inputs are converted to codes by rounding to nearest. */
  private lazy val angleError: Double = math.Pi / math.pow(2.0, angleBits)
  private lazy val vIn = robot.maxVelocity.map(v => Bounded(v, 0.5 * math.pow(2.0, -velocityFracBits)))
  private lazy val aIn = robot.maxAcceleration.map(a => Bounded(a, 0.5 * math.pow(2.0, -accelerationFracBits)))

  // ---- folded constants ----
  private def quantizeConst(k: Double): BigInt = FixedFormat(0, constantFracBits).quantize(k, Rounding.HalfUp)
  lazy val constA: BigInt = quantizeConst(robot.a)
  lazy val constB: BigInt = quantizeConst(robot.b)
  lazy val constC: BigInt = quantizeConst(robot.c)
  lazy val constD: BigInt = quantizeConst(robot.d)
  private def boundedConst(k: Double, raw: BigInt) = Bounded.constant(k, FixedFormat.scaleDown(raw, constantFracBits))
  if (model.closedForm) require(Seq(constA, constB, constC).forall(_ > 0),
    s"LoadParams.constantFracBits ($constantFracBits) is too few: a robot constant rounds to zero")

  // ---- the datapath, node by node (names as in LoadRecipe) ----
  private def product(x: Bounded, y: Bounded) = (x * y).rounded(lsbF, productRounding)

  lazy val v12: Bounded = vIn(0) + vIn(1)
  lazy val a2: Bounded = aIn(0) + aIn(1).scale(model.dd2Weight)
  lazy val a12: Bounded = aIn(0) + aIn(1)
  lazy val a3: Bounded = a12 + aIn(2)
  lazy val sq1: Bounded = product(vIn(0), vIn(0))
  lazy val sq12: Bounded = product(v12, v12)
  lazy val u1: Bounded = product(boundedConst(robot.a, constA), aIn(0))
  lazy val u2: Bounded = product(boundedConst(robot.b, constB), a2)
  lazy val u3: Bounded = product(boundedConst(robot.a, constA), sq1)
  lazy val u4: Bounded = product(boundedConst(robot.b, constB), sq12)
  lazy val u5: Bounded = product(boundedConst(robot.c, constC), a3)
  /** sin/cos of an angle built from `n` rounded input angles. */
  private def trig(n: Int) = Bounded(1.0, cordic.errorBound + n * angleError)
  lazy val p1: Bounded = product(u1, trig(2)) // A dd1 cos(t2+t3)
  lazy val p2: Bounded = product(u2, trig(1)) // B (dd1 + k dd2) cos t3
  lazy val p3: Bounded = product(u3, trig(2)) // A d1^2 sin(t2+t3)
  lazy val p4: Bounded = product(u4, trig(1)) // B (d1+d2)^2 sin t3
  lazy val p6: Bounded = product(boundedConst(robot.d, constD), trig(3)) // D sin(t1+t2+t3)
  lazy val s12: Bounded = p1 + p2
  lazy val s34: Bounded = p3 + p4
  lazy val s56: Bounded = p6 + u5
  lazy val s1234: Bounded = s12 + s34
  lazy val total: Bounded = s1234 + s56
  lazy val output: Bounded = total.rounded(math.pow(2.0, -outputFracBits), Rounding.HalfUp)

  /** Fixed-point format of every internal node, in datapath order, for the recipe and the report. */
  lazy val formats: Map[String, FixedFormat] = Map(
    "v12" -> v12.format(velocityFracBits),
    "a2" -> a2.format(accelerationFracBits),
    "a12" -> a12.format(accelerationFracBits),
    "a3" -> a3.format(accelerationFracBits),
    "sq1" -> sq1.format(F),
    "sq12" -> sq12.format(F),
    "u1" -> u1.format(F),
    "u2" -> u2.format(F),
    "u3" -> u3.format(F),
    "u4" -> u4.format(F),
    "u5" -> u5.format(F),
    "p1" -> p1.format(F),
    "p2" -> p2.format(F),
    "p3" -> p3.format(F),
    "p4" -> p4.format(F),
    "p6" -> p6.format(F),
    "s12" -> s12.format(F),
    "s34" -> s34.format(F),
    "s56" -> s56.format(F),
    "s1234" -> s1234.format(F),
    "total" -> total.format(F)
  )
  def fmt(node: String): FixedFormat = formats.getOrElse(node, throw new NoSuchElementException(s"no format for node $node"))

  lazy val constantFormat: FixedFormat = FixedFormat.forRawRange(Seq(constA, constB, constC, constD).max, constantFracBits)

  /** Load output, N·m. */
  lazy val outputFormat: FixedFormat = output.format(outputFracBits)

  /** Worst-case |load - exact double torque at the unquantized inputs|, N·m, for inputs in range. */
  lazy val errorBound: Double = output.error

  /** Largest |load| the declared ranges allow (sum of the six term maxima). */
  lazy val loadRange: Double = total.maxAbs

  if (model.closedForm) require(outputFormat.width <= 64, s"LoadParams: the declared ranges need a ${outputFormat.width}-bit output; narrow the ranges")

  def tag: String = s"${model.name}_${cordic.tag}_f$F"
}

object LoadParams {

  /** Exact model, error well under 1e-4 N·m for the typical arm (SPEC.md). */
  val default: LoadParams = LoadParams()

  /**
   * The paper's equation (6), sized for the paper's accuracy: derived bound <= 1e-3 N·m, with the
   * table-assisted residual CORDIC (22 bits, 1024-entry table, no shift-add stage: the residual
   * rotation starts right after the table) and every delay of 3 clocks or more in block RAM.
   */
  val paper: LoadParams = LoadParams(
    model = LoadModel.PaperEq6,
    cordic = CordicParams(angleBits = 22, outputBits = 22, iterations = 11, guardBits = 3, angleGuardBits = 4,
      architecture = reducerload.cordic.CordicArchitecture.ResidualRotation, tableBits = 10),
    velocityFracBits = 16,
    accelerationFracBits = 16,
    constantFracBits = 19,
    internalFracBits = 16,
    outputFracBits = 16,
    memoryDelayMinCycles = 3
  )

  /**
   * The paper's accuracy (derived bound <= 1e-3 N·m, exact model) in the fewest logic elements: the
   * `paper` preset's arithmetic with one CORDIC unit shared by the three angles, so one sample every
   * 3 clocks (50 M samples/s at 150 MHz, far above any control loop's rate).
   */
  val compact: LoadParams = paper.copy(model = LoadModel.Exact, cordicUnits = 1)

  /**
   * The end of the trade with the fewest resources: 16-bit table-assisted residual CORDIC, one unit
   * shared by the three angles (one sample every 3 clocks; about 2e-2 N·m).
   */
  val smallest: LoadParams = LoadParams(
    cordic = CordicParams(angleBits = 16, outputBits = 16, iterations = 6, guardBits = 3, angleGuardBits = 4,
      architecture = reducerload.cordic.CordicArchitecture.ResidualRotation, tableBits = 4),
    velocityFracBits = 12, accelerationFracBits = 12, constantFracBits = 16, internalFracBits = 12, outputFracBits = 12,
    cordicUnits = 1)

  /** The most accurate: classic 30-bit CORDIC, wide datapath. */
  val accurate: LoadParams = LoadParams(
    cordic = CordicParams(angleBits = 30, outputBits = 30, iterations = 30, guardBits = 5, angleGuardBits = 5),
    velocityFracBits = 24, accelerationFracBits = 24, constantFracBits = 28, internalFracBits = 24, outputFracBits = 24)

  /**
   * The highest clock and load rate within the paper's accuracy (derived bound <= 1e-3 N·m): a
   * 23-bit classic CORDIC, whose short carry chains, with no table ROM and no multiply in the
   * angle path, measured the fastest in the sweep (`classic-b23-n20`); paid for in logic elements.
   */
  val fastest: LoadParams = LoadParams(
    cordic = CordicParams(angleBits = 23, outputBits = 23, iterations = 20, guardBits = 3, angleGuardBits = 4),
    velocityFracBits = 17, accelerationFracBits = 17, constantFracBits = 21, internalFracBits = 17, outputFracBits = 17)

  /**
   * Every joint of an arm (model rnea; `--robot` starts from it): a 28-bit table-assisted residual
   * CORDIC and 24 fraction bits inside, for derived bounds under 1e-3 N·m on the UR5 and the Panda
   * at their declared ranges (where |qd| of every joint at once makes the worst case far above
   * the torques of real motions). Shown on the built-in planar3; `--robot FILE.urdf` swaps the robot.
   */
  val arm: LoadParams = LoadParams(
    model = LoadModel.Rnea,
    cordic = CordicParams(angleBits = 28, outputBits = 28, iterations = 16,
      architecture = reducerload.cordic.CordicArchitecture.ResidualRotation, tableBits = 9),
    velocityFracBits = 24, accelerationFracBits = 22, constantFracBits = 28, internalFracBits = 24, outputFracBits = 20)

  /** The arm presets (every joint; not in the joint-3 preset table or sweep). */
  val armPresets: scala.collection.immutable.ListMap[String, LoadParams] = scala.collection.immutable.ListMap("arm" -> arm)

  /** Every preset `--preset` accepts. */
  def allPresets: scala.collection.immutable.ListMap[String, LoadParams] = presets ++ armPresets

  /** The shipped presets, in the order the README and the sweep list them. */
  val presets: scala.collection.immutable.ListMap[String, LoadParams] = scala.collection.immutable.ListMap(
    "default" -> default, "paper" -> paper, "compact" -> compact, "smallest" -> smallest, "accurate" -> accurate, "fastest" -> fastest)
}
