package reducerload.compiler

import reducerload.arm.{ArmParams, Dynamics, GravitySpec, PayloadSpec}
import reducerload.config.LoadParams
import reducerload.graph.BankedSchedule
import reducerload.monitor.{MonitorConfig, MonitorParams, RatedReducer}
import reducerload.robot.{RobotParams, SerialChain}
import reducerload.util.{InputError, Warning}

/**
 * A configuration compiled: the arm datapath's parameters with every derived fact forced once (chain, graph,
 * analysis and target-error fit, device fit, schedule, banked schedule) and, with `monitor.enabled`, the
 * monitor resolved against the arm. Emit, simulate, sweep and soak consume this; none compiles again.
 *
 * @param config
 *   the configuration as given (`auto` kept: the fit's choices are in `arm.scheduleRequest`)
 * @param fit
 *   the design's use of the target device and, when the fit chose it, why
 */
final case class Compiled(
    config: LoadParams,
    arm: ArmParams,
    monitor: Option[MonitorParams],
    rated: IndexedSeq[Option[RatedReducer]],
    fit: Fitted
) {
  def banked: Option[BankedSchedule] = arm.banked

  /** What the user should know about this design, in the order found (robot first, then the device). */
  def warnings: Seq[Warning] = arm.chain.warnings ++ fit.warnings
}

/**
 * The compiler pipeline: robot -> chain -> graph -> analysis / target-error fit -> device fit -> schedule ->
 * banks.
 */
object Compiler {

  /**
   * Compile `p`; `source` names the configuration (file, preset, flags) in the one-line error a refusal
   * becomes.
   */
  def compile(p: LoadParams, source: String): Compiled =
    refusedAs(source) {
      val fit = DeviceFit(p, arm(p))
      val a = fit.design.arm
      a.schedule
      a.banked
      val monitor = if (p.monitor.enabled) Some(MonitorConfig(a, p.monitor)) else None
      val rated =
        if (p.monitor.enabled) MonitorConfig.rated(a, p.monitor) else IndexedSeq.fill(a.chain.size)(None)
      Compiled(p, a, monitor, rated, fit)
    }

  /** `body`, a refusal of the configuration (a failed `require`) one line naming `source`. */
  def refusedAs[A](source: String)(body: => A): A =
    try body
    catch {
      case e: IllegalArgumentException =>
        throw new InputError(s"$source: ${e.getMessage.stripPrefix("requirement failed: ")}")
    }

  /**
   * The datapath's parameters (fraction bits fitted to `numeric.target-error` if set); lazy in the schedule,
   * which [[compile]] forces.
   */
  def arm(p: LoadParams): ArmParams = {
    val asSet = configured(p)
    if (p.targetError.isEmpty) asSet
    else TargetFit.fitted(asSet, TargetFit.perOutput(asSet, p.targetError))
  }

  /** One value for every joint, one per joint, or (velocities only) none: the URDF's limits. */
  private def perJoint(
      chain: SerialChain,
      values: Seq[Double],
      key: String,
      fromUrdf: Option[IndexedSeq[Option[Double]]]
  ): Seq[Double] =
    values.size match {
      case 0 =>
        val limits =
          fromUrdf.getOrElse(throw new IllegalArgumentException(s"$key must be declared for ${chain.name}"))
        val taken = chain.joints.zip(limits).map { case (j, l) =>
          l.getOrElse(
            throw new IllegalArgumentException(
              s"${chain.label}: joint '${j.name}' has no <limit velocity>: declare $key"
            )
          )
        }
        // The file's limits meet the declared ranges' rule; a refusal points at the file.
        try RobotParams.checkRanges(taken, Nil)
        catch {
          case e: IllegalArgumentException =>
            throw new IllegalArgumentException(
              s"${chain.label}: <limit velocity> taken for ${e.getMessage.stripPrefix("requirement failed: ")}; declare $key"
            )
        }
        taken
      case 1                    => Seq.fill(chain.size)(values.head)
      case n if n == chain.size => values
      case n =>
        throw new IllegalArgumentException(
          s"robot ${chain.name} has ${chain.size} joints but $key gives $n values"
        )
    }

  /** The payload's declared set, stated in a link the last moving joint carries (the tip by default). */
  private def payload(p: LoadParams, chain: SerialChain): PayloadSpec = {
    val frame = Option(p.payload.frame).filter(_.nonEmpty).getOrElse(chain.tip)
    val pose = chain.tipFrames.getOrElse(
      frame,
      throw new InputError(
        s"${chain.label}: payload.frame: link '$frame' is not fixed to the last moving joint " +
          s"'${chain.joints.last.name}' (links it carries: ${chain.tipFrames.keys.toSeq.sorted.mkString(", ")})"
      )
    )
    PayloadSpec(frame, pose, p.payload.maxMass, p.payload.comRadius, p.payload.maxGyrationRadius)
  }

  /** The run-time gravity's declared bound, which must hold the chain's own gravity (its reset value). */
  private def gravity(p: LoadParams, chain: SerialChain): GravitySpec = {
    val g = chain.gravity.norm
    if (g > p.gravity.maxMagnitude)
      throw new InputError(
        s"${chain.label}: gravity.max-magnitude: ${p.gravity.maxMagnitude} m/s^2 is below the robot's own " +
          s"gravity ($g m/s^2), the run-time gravity's reset value"
      )
    GravitySpec(p.gravity.maxMagnitude)
  }

  private def configured(p: LoadParams): ArmParams = {
    val c = p.robot.chain
    ArmParams(
      c,
      perJoint(c, p.robot.maxVelocity, "robot.max-velocity", Some(c.joints.map(_.velocityLimit))),
      perJoint(c, p.robot.maxAcceleration, "robot.max-acceleration", None),
      p.cordic,
      datapath = p.datapath,
      scheduleRequest = p.schedule,
      dynamics = if (p.model.closedForm) Dynamics.Joint3(p.model, p.robot) else Dynamics.Rnea,
      payload = Option.when(p.payload.enabled)(payload(p, c)),
      gravity = Option.when(p.gravity.runtime)(gravity(p, c))
    )
  }
}
