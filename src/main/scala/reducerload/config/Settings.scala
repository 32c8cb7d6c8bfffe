package reducerload.config

import com.typesafe.config.{Config, ConfigException, ConfigValueType}
import reducerload.cordic.{CordicArchitecture, CordicParams}
import reducerload.fixedpoint.Rounding
import reducerload.graph.{
  ConstantMultiplies,
  ListOrder,
  ProductMemory,
  Reassociation,
  ScheduleRequest,
  Scheduler,
  Storage
}
import reducerload.load.LoadModel
import reducerload.robot.{Mounting, RobotParams}
import reducerload.util.InputError

import scala.jdk.CollectionConverters._

/**
 * One configuration key: its HOCON path, unit, meaning, flag aliases, value type `T`, and where the value
 * lives in [[LoadParams]] (`get`; the default is [[LoadParams.default]]'s, the bounds are the
 * sub-configuration's `require`s).
 */
sealed abstract class Setting[T](
    val key: String,
    val unit: String,
    val help: String,
    val aliases: Seq[String],
    val get: LoadParams => T
) {

  /** Read and type-check the value at `key`; `source` names the file or flag for errors. */
  def read(c: Config, source: String): T

  /** A value as HOCON text. */
  def show(value: T): String

  /** The value in `p`, as HOCON text. */
  final def render(p: LoadParams): String = show(get(p))

  /** The type, for --help. */
  def typeName: String

  protected def wrongType(source: String, expected: String, c: Config): Nothing =
    throw new InputError(s"$source: key '$key' must be $expected, got ${Setting.show(c, key)}")
}

object Setting {
  private[config] def show(c: Config, key: String): String = {
    val v = c.getValue(key)
    s"${v.valueType().name().toLowerCase} ${v.render(com.typesafe.config.ConfigRenderOptions.concise())}"
  }

  private def whole(d: Double) = d == math.rint(d) && math.abs(d) < 1e9

  final class Real(key: String, unit: String, help: String, aliases: Seq[String], get: LoadParams => Double)
      extends Setting[Double](key, unit, help, aliases, get) {
    def show(v: Double): String = v.toString
    def typeName = "number"
    def read(c: Config, source: String): Double =
      if (c.getValue(key).valueType() != ConfigValueType.NUMBER) wrongType(source, "a number", c)
      else c.getDouble(key)
  }

  final class Natural(key: String, unit: String, help: String, aliases: Seq[String], get: LoadParams => Int)
      extends Setting[Int](key, unit, help, aliases, get) {
    def show(v: Int): String = v.toString
    def typeName = "integer"
    def read(c: Config, source: String): Int =
      if (c.getValue(key).valueType() == ConfigValueType.NUMBER && whole(c.getDouble(key)))
        c.getDouble(key).toInt
      else wrongType(source, "an integer", c)
  }

  /** One of a few named values (`name` gives each its configuration word). */
  final class Choice[T](
      key: String,
      unit: String,
      help: String,
      aliases: Seq[String],
      val choices: Seq[T],
      name: T => String,
      get: LoadParams => T
  ) extends Setting[T](key, unit, help, aliases, get) {
    private val names = choices.map(name)
    def show(v: T): String = name(v)
    def typeName: String = names.mkString("|")
    def read(c: Config, source: String): T = {
      if (c.getValue(key).valueType() != ConfigValueType.STRING)
        wrongType(source, s"one of ${names.mkString(", ")}", c)
      val s = c.getString(key)
      choices
        .find(name(_) == s)
        .getOrElse(
          throw new InputError(s"$source: key '$key' must be one of ${names.mkString(", ")}, got '$s'")
        )
    }
  }

  /** A string (a file path or a name). */
  final class Text(key: String, unit: String, help: String, aliases: Seq[String], get: LoadParams => String)
      extends Setting[String](key, unit, help, aliases, get) {
    def show(v: String): String = com.typesafe.config.ConfigValueFactory.fromAnyRef(v).render()
    def typeName = "string"
    def read(c: Config, source: String): String =
      if (c.getValue(key).valueType() != ConfigValueType.STRING) wrongType(source, "a string", c)
      else c.getString(key)
  }

  /** On or off (HOCON true/false). */
  final class Switch(
      key: String,
      unit: String,
      help: String,
      aliases: Seq[String],
      get: LoadParams => Boolean
  ) extends Setting[Boolean](key, unit, help, aliases, get) {
    def show(v: Boolean): String = v.toString
    def typeName = "true|false"
    def read(c: Config, source: String): Boolean =
      if (c.getValue(key).valueType() != ConfigValueType.BOOLEAN) wrongType(source, "true or false", c)
      else c.getBoolean(key)
  }

  /** On, off, or `auto` (read as None) for a choice the compiler makes. */
  final class AutoSwitch(
      key: String,
      unit: String,
      help: String,
      aliases: Seq[String],
      get: LoadParams => Option[Boolean]
  ) extends Setting[Option[Boolean]](key, unit, help, aliases, get) {
    def show(v: Option[Boolean]): String = v.fold("auto")(_.toString)
    def typeName = "true|false|auto"
    def read(c: Config, source: String): Option[Boolean] = c.getValue(key).valueType() match {
      case ConfigValueType.BOOLEAN                              => Some(c.getBoolean(key))
      case ConfigValueType.STRING if c.getString(key) == "auto" => None
      case _                                                    => wrongType(source, "true, false or auto", c)
    }
  }

  /** A whole number, or `keyword` for a derived or absent value (read as None). */
  final class Count(
      key: String,
      unit: String,
      help: String,
      aliases: Seq[String],
      keyword: String,
      get: LoadParams => Option[Int]
  ) extends Setting[Option[Int]](key, unit, help, aliases, get) {
    def show(v: Option[Int]): String = v.fold(keyword)(_.toString)
    def typeName = s"integer or $keyword"
    def read(c: Config, source: String): Option[Int] = c.getValue(key).valueType() match {
      case ConfigValueType.STRING if c.getString(key) == keyword => None
      case ConfigValueType.NUMBER if whole(c.getDouble(key))     => Some(c.getDouble(key).toInt)
      case _ => wrongType(source, s"an integer or $keyword", c)
    }
  }

  /**
   * The robot base's orientation: a named mounting (`floor`, `ceiling`, `wall`) or `[roll, pitch, yaw]` in
   * rad (URDF convention).
   */
  final class Orientation(key: String, help: String, aliases: Seq[String], get: LoadParams => Mounting)
      extends Setting[Mounting](key, "rad", help, aliases, get) {
    private val names = Mounting.named.map(_._1)
    private val expected = s"${names.mkString(", ")} or [roll, pitch, yaw]"
    def show(v: Mounting): String = v.name.getOrElse(Seq(v.roll, v.pitch, v.yaw).mkString("[", ", ", "]"))
    def typeName: String = names.mkString("", "|", "|[roll, pitch, yaw]")
    def read(c: Config, source: String): Mounting = c.getValue(key).valueType() match {
      case ConfigValueType.STRING =>
        val s = c.getString(key)
        Mounting.named
          .collectFirst { case (n, m) if n == s => m }
          .getOrElse(throw new InputError(s"$source: key '$key' must be $expected, got '$s'"))
      case ConfigValueType.LIST =>
        val items = c.getList(key).asScala.toSeq
        if (items.size != 3 || items.exists(_.valueType() != ConfigValueType.NUMBER))
          wrongType(source, s"$expected (three numbers, rad)", c)
        val a = items.map(_.unwrapped().asInstanceOf[Number].doubleValue())
        try Mounting(a(0), a(1), a(2))
        catch {
          case e: IllegalArgumentException =>
            throw new InputError(s"$source: ${e.getMessage.stripPrefix("requirement failed: ")}")
        }
      case _ => wrongType(source, expected, c)
    }
  }

  /**
   * One value per joint: a single number stands for every joint, a list gives each joint its own (the joint
   * count comes from the robot, not from here), and `keyword` (if any) stands for a derived value, read as an
   * empty Seq: `urdf` takes the URDF's limits, `auto` a derived width, `none` leaves the value out. `integer`
   * values must be whole numbers.
   */
  final class PerJoint(
      key: String,
      unit: String,
      help: String,
      aliases: Seq[String],
      get: LoadParams => Seq[Double],
      keyword: Option[String] = None,
      integer: Boolean = false
  ) extends Setting[Seq[Double]](key, unit, help, aliases, get) {
    private def one(x: Double): String = if (integer) x.toLong.toString else x.toString
    def show(v: Seq[Double]): String = v match {
      case Seq()  => keyword.getOrElse("[]")
      case Seq(x) => one(x)
      case values => values.map(one).mkString("[", ", ", "]")
    }
    private val kind = if (integer) "integer" else "number"
    def typeName: String = s"$kind or [n1, ..., nN]" + keyword.fold("")(k => s" or $k")
    def read(c: Config, source: String): Seq[Double] = {
      def checked(xs: Seq[Double]): Seq[Double] =
        if (integer && !xs.forall(whole))
          wrongType(source, "an integer or a list of integers (one per joint)", c)
        else xs
      c.getValue(key).valueType() match {
        case ConfigValueType.NUMBER                                       => checked(Seq(c.getDouble(key)))
        case ConfigValueType.STRING if keyword.contains(c.getString(key)) => Seq.empty[Double]
        case ConfigValueType.LIST =>
          val items = c.getList(key).asScala.toSeq
          if (items.isEmpty || items.exists(_.valueType() != ConfigValueType.NUMBER))
            wrongType(source, s"a list of ${kind}s (one per joint)", c)
          checked(items.map(_.unwrapped().asInstanceOf[Number].doubleValue()))
        case _ => wrongType(source, s"a $kind or a list of ${kind}s${keyword.fold("")(k => s" or $k")}", c)
      }
    }
  }
}

/** A setting's value from the command line, parsed to the setting's type. */
final case class Assignment[T](setting: Setting[T], value: T)

/** Every key of a configuration, with units and defaults: the single source of --help and the docs table. */
object Settings {
  import Setting._

  val robotSource = new Text(
    "robot.source",
    "",
    "planar3 (the built-in planar arm below) or the path of a URDF file",
    Seq("robot"),
    _.robot.source
  )

  val robotTip = new Text(
    "robot.tip",
    "",
    "URDF link that ends the chain (empty: the only leaf)",
    Seq("tip"),
    _.robot.tip
  )

  val robotAllowMassless = new Switch(
    "robot.allow-massless",
    "",
    "accept a URDF whose last joints move no mass (every link from the joint's to the tip without <inertial> " +
      "or with zero mass: a torque identically zero), with a warning; false refuses it. A moving link without " +
      "<inertial> is taken as massless with a warning either way; links fixed to another link (tool0, flange) are frames",
    Nil,
    _.robot.allowMassless
  )

  val robotM3 = new Real("robot.m3", "kg", "planar3: point mass at the end of link 3", Seq("m3"), _.robot.m3)

  val robotL1 = new Real("robot.l1", "m", "planar3: length of link 1", Seq("l1"), _.robot.l1)

  val robotL2 = new Real("robot.l2", "m", "planar3: length of link 2", Seq("l2"), _.robot.l2)

  val robotL3 = new Real("robot.l3", "m", "planar3: length of link 3", Seq("l3"), _.robot.l3)

  val robotG = new Real(
    "robot.g",
    "m/s^2",
    "planar3: gravitational acceleration (t1 = 0 points link 1 down; a URDF robot has 9.81 along -z)",
    Seq("g"),
    _.robot.g
  )

  val robotBaseRpy = new Orientation(
    Mounting.setting,
    "the base's orientation in the world (URDF roll, pitch, yaw), whose gravity is (0, 0, -g) (planar3: its own " +
      "(+g, 0, 0)); R(rpy)^T times it, the gravity in base coordinates, is folded at elaboration. floor = [0, 0, 0]; " +
      "ceiling = [pi, 0, 0]; wall = [0, pi/2, 0]: base z along world +x, base x down, gravity along base +x",
    Seq("base-rpy", "mounting"),
    _.robot.mounting
  )

  val robotMaxVelocity = new PerJoint(
    "robot.max-velocity",
    "rad/s",
    "declared max |velocity| per joint (urdf: the URDF's <limit velocity>)",
    Seq("max-velocity"),
    _.robot.maxVelocity,
    keyword = Some("urdf")
  )

  val robotMaxAcceleration = new PerJoint(
    "robot.max-acceleration",
    "rad/s^2",
    "declared max |acceleration| per joint (a URDF has none: declare it)",
    Seq("max-acceleration"),
    _.robot.maxAcceleration
  )

  val payloadEnabled = new Switch(
    "payload.enabled",
    "",
    "the payload on the last joint as ten run-time inputs (mass, centre of mass, inertia about it in the payload " +
      "frame) within the declared set below: one design serves every payload in it (model rnea; docs/payload.md)",
    Nil,
    _.payload.enabled
  )

  val payloadMaxMass = new Real(
    "payload.max-mass",
    "kg",
    "heaviest payload (must be declared with payload.enabled)",
    Nil,
    _.payload.maxMass
  )

  val payloadComRadius = new Real(
    "payload.com-radius",
    "m",
    "each coordinate of the payload's centre of mass within this distance of the payload frame's origin",
    Nil,
    _.payload.comRadius
  )

  val payloadMaxGyrationRadius = new Real(
    "payload.max-gyration-radius",
    "m",
    "bounds every element of the payload's inertia about its centre of mass by max-mass x radius^2",
    Nil,
    _.payload.maxGyrationRadius
  )

  val payloadFrame = new Text(
    "payload.frame",
    "",
    "URDF link the payload is stated in, fixed to the last moving joint (empty: the tip link)",
    Nil,
    _.payload.frame
  )

  val gravityRuntime = new Switch(
    "gravity.runtime",
    "",
    "the gravity vector (base coordinates) as three run-time inputs within gravity.max-magnitude, host-written and " +
      "committed like the payload (arms on moving platforms); reset: the robot's gravity rotated by robot.base-rpy " +
      "(model rnea; docs/payload.md)",
    Nil,
    _.gravity.runtime
  )

  val gravityMaxMagnitude = new Real(
    "gravity.max-magnitude",
    "m/s^2",
    "bound on the run-time gravity: each component within [-bound, bound] (default 1.5 g)",
    Nil,
    _.gravity.maxMagnitude
  )

  val model = new Choice(
    "model",
    "",
    "exact (tau3 of docs/equations.md) or paper (equation (6) as published): planar3's joint 3; rnea: every joint of any robot",
    Nil,
    LoadModel.all,
    (m: LoadModel) => m.name,
    _.model
  )

  val cordicAngleBits = new Natural(
    "cordic.angle-bits",
    "bits",
    "binary-angle width (full turn = 2^bits)",
    Nil,
    _.cordic.angleBits
  )

  val cordicOutputBits =
    new Natural("cordic.output-bits", "bits", "sin/cos width, format Q1.(bits-2)", Nil, _.cordic.outputBits)

  val cordicIterations = new Natural(
    "cordic.iterations",
    "",
    "CORDIC micro-rotations (iteration 0 folded)",
    Nil,
    _.cordic.iterations
  )

  val cordicGuardBits =
    new Natural("cordic.guard-bits", "bits", "extra fraction bits in x, y", Nil, _.cordic.guardBits)

  val cordicAngleGuardBits = new Natural(
    "cordic.angle-guard-bits",
    "bits",
    "extra fraction bits in the angle accumulator",
    Nil,
    _.cordic.angleGuardBits
  )

  val cordicOutputRounding = new Choice(
    "cordic.output-rounding",
    "",
    "sin/cos output rounding",
    Nil,
    Rounding.all,
    (r: Rounding) => r.name,
    _.cordic.outputRounding
  )

  val cordicIterationsPerStage = new Natural(
    "cordic.iterations-per-stage",
    "",
    "micro-rotations between pipeline registers",
    Nil,
    _.cordic.iterationsPerStage
  )

  val cordicArchitecture = new Choice(
    "cordic.architecture",
    "",
    "classic (shift-add only) or residual (shift-add, then one multiply-based rotation)",
    Nil,
    CordicArchitecture.all,
    (a: CordicArchitecture) => a.name,
    _.cordic.architecture
  )

  val cordicTableBits = new Natural(
    "cordic.table-bits",
    "bits",
    "start-vector table (ROM) of 2^bits entries replacing iterations 0..bits (0: none)",
    Nil,
    _.cordic.tableBits
  )

  val datapathVelocityFracBits = new Natural(
    "datapath.velocity-frac-bits",
    "bits",
    "fraction bits of velocity inputs (rad/s)",
    Nil,
    _.datapath.velocityFracBits
  )

  val datapathAccelerationFracBits = new Natural(
    "datapath.acceleration-frac-bits",
    "bits",
    "fraction bits of acceleration inputs (rad/s^2)",
    Nil,
    _.datapath.accelerationFracBits
  )

  val datapathConstantFracBits = new Natural(
    "datapath.constant-frac-bits",
    "bits",
    "fraction bits of folded robot constants",
    Nil,
    _.datapath.constantFracBits
  )

  val datapathInternalFracBits = new Natural(
    "datapath.internal-frac-bits",
    "bits",
    "fraction bits of products and sums",
    Nil,
    _.datapath.internalFracBits
  )

  val datapathOutputFracBits = new Natural(
    "datapath.output-frac-bits",
    "bits",
    "fraction bits of the load output (N·m)",
    Nil,
    _.datapath.outputFracBits
  )

  val datapathProductRounding = new Choice(
    "datapath.product-rounding",
    "",
    "rounding of products to internal-frac-bits",
    Nil,
    Rounding.all,
    (r: Rounding) => r.name,
    _.datapath.productRounding
  )

  val datapathMultiplierLatency = new Natural(
    "datapath.multiplier-latency",
    "cycles",
    "registers after each multiplier",
    Nil,
    _.datapath.multiplierLatency
  )

  val datapathMemoryDelayMinCycles = new Natural(
    "datapath.memory-delay-min-cycles",
    "cycles",
    "values held this long or longer wait in block RAM instead of registers: stretches of a delay line at one " +
      "clock per sample, reads an interval or more after a value's first register with storage registers " +
      "(0: registers only; the device fit uses 0 where only these delays' block RAM keeps a design off the device)",
    Nil,
    _.datapath.memoryDelayMinCycles
  )

  val datapathRegisteredRoutes = new AutoSwitch(
    "datapath.registered-routes",
    "",
    "registers storage at 2 clocks per sample or more: each shared multiplier's operands pass two registered " +
      "multiplexer levels, no product is forwarded (but those schedule.forward-slack names), each held " +
      "register has a copy of its write enable of its own (2 clocks more per multiply, one more in the output " +
      "stage): designs that route and clock on a full " +
      "device; wherever routes are registered the CORDIC table's block RAM also gets a register in logic (one " +
      "clock more per sin/cos; true: at any interval and storage); auto: above " +
      s"${reducerload.graph.Schedule.directMaxClocks} clocks per sample, whichever the device fit chooses (the " +
      "table's register in either storage)",
    Nil,
    _.datapath.registeredRoutes
  )

  val datapathReassociate = new Choice(
    "datapath.reassociate",
    "",
    "off (sums as RNEA writes them, left to right), sums (each sum of several terms rebuilt as a tree, " +
      "the earliest terms first: a shorter critical path; the same values, their formats and bounds derived anew) " +
      "or sums-and-products (also each product of several factors, two earliest first, and each constant on the " +
      "critical path pushed into the sum it scales, a sum read only there or a rotation: a shorter critical path " +
      "still, for a few more products)",
    Nil,
    Reassociation.all,
    (r: Reassociation) => r.name,
    _.datapath.reassociate
  )

  val datapathComposeParallelAxes = new Switch(
    "datapath.compose-parallel-axes",
    "",
    "model rnea: each run of consecutive joints with parallel axes (a UR5's shoulder, elbow and wrist 1) is " +
      "crossed in one rotation by its summed angle, in both passes: fewer multiply levels on the critical path " +
      "(a shorter latency) for more products and sin/cos pairs (docs/design.md, \"Parallel axes\")",
    Nil,
    _.datapath.composeParallelAxes
  )

  val scheduleClocksPerSample = new Count(
    "schedule.clocks-per-sample",
    "clocks",
    "clocks between samples (the initiation interval; auto: chosen by the device fit, the fewest whose design fits " +
      "the device and max-multipliers)",
    Seq("clocks-per-sample"),
    "auto",
    _.schedule.clocksPerSample
  )

  val scheduleMaxMultipliers = new Count(
    "schedule.max-multipliers",
    "18x18 blocks",
    "18x18 multiplier blocks the datapath may use, its CORDIC units' included (none: no budget; a monitor's come on top)",
    Seq("max-multipliers"),
    "none",
    _.schedule.maxMultipliers
  )

  val scheduleCordicUnits = new Count(
    "schedule.cordic-units",
    "",
    "sin/cos units shared by the angles (auto: the fewest that keep clocks-per-sample)",
    Nil,
    "auto",
    _.schedule.cordicUnits
  )

  val scheduleStorage = new Choice(
    "schedule.storage",
    "",
    "clocks-per-sample >= 2: registers (every value its own registers, operands multiplexed) or memory " +
      "(values in block-RAM banks read by address, adders shared too: far fewer logic elements); auto: chosen " +
      "by the device fit (registers when they fit)",
    Nil,
    None +: Storage.all.map(Some(_)),
    (s: Option[Storage]) => s.fold("auto")(_.name),
    _.schedule.storage
  )

  val scheduleConstantMultiplies = new Choice(
    "schedule.constant-multiplies",
    "",
    "multiplies by a folded robot constant: blocks (on the 18x18 multiplier units) or shift-add " +
      "(the constant's signed digits summed in logic elements: no multiplier block, more logic; storage registers only)",
    Nil,
    ConstantMultiplies.all,
    (c: ConstantMultiplies) => c.name,
    _.schedule.constantMultiplies
  )

  val scheduleListOrder = new Choice(
    "schedule.list-order",
    "",
    "storage memory: the list scheduler's order, by-height (each operation, critical path first, at its " +
      "first free cycle) or by-cycle (each cycle's ready operations, critical path first); auto: both, the " +
      "shorter latency kept; storage registers: by-height, or auto for the graph's order",
    Nil,
    None +: ListOrder.all.map(Some(_)),
    (o: Option[ListOrder]) => o.fold("auto")(_.name),
    _.schedule.listOrder
  )

  val scheduleListTries = new Natural(
    "schedule.list-tries",
    "",
    "storage memory: by-height schedules tried, the first in the plain order, the others with each " +
      "priority raised by 0 or 1 (seeded, so the same every run); the shortest kept",
    Nil,
    _.schedule.listTries
  )

  val scheduleRefinement = new Natural(
    "schedule.refinement",
    "steps per operation",
    "storage registers, clocks-per-sample >= 2: annealing steps (seeded, so the same every run) moving the list " +
      "schedule's cycles, units and operand order so that operand multiplexers and held registers take the fewest " +
      "logic elements at no more latency (0: the list schedule as it is; the device fit refines a candidate just " +
      "over its logic budget again with more steps and says so)",
    Nil,
    _.schedule.refinement
  )

  val scheduleScheduler = new Choice(
    "schedule.scheduler",
    "",
    "storage registers, clocks-per-sample >= 2: list (the list schedule) or cp-sat (then the shortest latency " +
      "OR-Tools CP-SAT finds from it under the same units, seeded and deterministic; the refinement then has less " +
      "slack: the UR5 at 17 clocks 147 -> 142 cycles for ~5 % more logic elements)",
    Nil,
    Scheduler.all,
    (s: Scheduler) => s.name,
    _.schedule.scheduler
  )

  val scheduleShareRegisters = new Switch(
    "schedule.share-registers",
    "",
    "storage registers, clocks-per-sample >= 2: products of one multiplier unit, rounded alike, whose cycles " +
      "from ready to last read do not meet within the interval take turns in one register instead of a register " +
      "each (fewer logic elements; each member's bits as in its own register)",
    Nil,
    _.schedule.shareRegisters
  )

  val scheduleProductMemories = new Switch(
    "schedule.product-memories",
    "",
    "storage registers, clocks-per-sample >= 2: each multiplier unit writes its product into a block RAM every " +
      s"clock; truncated products read ${ProductMemory.readDelay} clocks or more after they are " +
      "ready, within the interval, are read from " +
      "it, one per cycle, instead of a register each, and the refinement moves reads there (fewer logic " +
      "elements, a memory block per unit; no more latency)",
    Nil,
    _.schedule.productMemories
  )

  val scheduleSinCosMemories = new Switch(
    "schedule.sin-cos-memories",
    "",
    "storage registers, clocks-per-sample >= 2: each CORDIC unit writes its sine and its cosine into block RAMs " +
      s"every clock; sin and cos reads ${ProductMemory.readDelay} clocks or more after the value is ready are " +
      "read from them, one per cycle and memory, instead of the value's registers (fewer logic elements and, " +
      "with block-RAM delays, fewer memory blocks; no more latency)",
    Nil,
    _.schedule.sinCosMemories
  )

  val scheduleReaderCopies = new Switch(
    "schedule.reader-copies",
    "",
    "datapath.registered-routes: a value several multiplier units read within the interval after it is ready " +
      "reaches each of them but one through a copy of its register loaded a clock later, placed beside that " +
      "unit (more logic elements, no more latency; no effect without registered routes)",
    Nil,
    _.schedule.readerCopies
  )

  val scheduleForwardSlack = new Count(
    "schedule.forward-slack",
    "clocks",
    "datapath.registered-routes: a product read by one addition only is taken off its unit's output a cycle " +
      "early, with no register of its own, when the dependences leave it at most this much slack (0: the " +
      "longest paths only; none: no product; direct routes forward every such product)",
    Nil,
    "none",
    _.schedule.forwardSlack
  )

  val scheduleAccumulateSlack = new Count(
    "schedule.accumulate-slack",
    "clocks",
    "storage registers, clocks-per-sample >= 2: a tree of additions whose leaves are products read once is " +
      "summed by an accumulator that takes each product from its unit in turn (no register per product, no " +
      "adder per sum: fewer logic elements), when the clocks that costs over adders (k products: k + 1 - " +
      "ceil(log2 k)) are within the dependences' slack of its root plus this many (none: no tree)",
    Nil,
    "none",
    _.schedule.accumulateSlack
  )

  val scheduleAdderUnits = new Count(
    "schedule.adder-units",
    "",
    "storage memory: shared adder units (auto: the fewest that take every addition; " +
      "more cost logic elements and shorten the latency)",
    Nil,
    "auto",
    _.schedule.adderUnits
  )

  val deviceName = new Choice(
    "device.name",
    "",
    "the target device: its 18x18 multiplier blocks, memory blocks and logic cells bound the design the fit " +
      "chooses and are compared with the design's in the report (docs/device.md)",
    Seq("device"),
    Device.all,
    (d: Device) => d.name,
    _.device.part
  )

  val busInterface = new Choice(
    "bus.interface",
    "",
    "the wrapper top run emit writes: avalon (Avalon-ST streams, Avalon-MM registers, interrupt: Platform Designer), " +
      "axi (AXI4-Stream, AXI4-Lite: Vivado) or none (the bare datapath or monitored arm, as before; docs/register-map.md)",
    Seq("bus"),
    BusKind.all,
    (b: BusKind) => b.name,
    _.bus.kind
  )

  val busTopName = new Text(
    "bus.top-name",
    "",
    "the wrapper's module name, the same for every robot and setting (bus.interface avalon or axi)",
    Nil,
    _.bus.topName
  )

  val deviceMaxLogicFraction = new Real(
    "device.max-logic-fraction",
    "",
    "share of the device's logic cells a design chosen by the fit may use: a nearly full Cyclone IV routes " +
      "and closes timing poorly (Quartus fits above about 85 % badly), and the user's own logic needs room",
    Nil,
    _.device.maxLogicFraction
  )

  val numericTargetError = new PerJoint(
    "numeric.target-error",
    "N·m",
    "derived error bound to meet per torque; the datapath's fraction bits become the fewest that meet it " +
      "(none: as set above)",
    Seq("target-error"),
    _.targetError,
    keyword = Some("none")
  )

  val monitorEnabled = new Switch(
    "monitor.enabled",
    "",
    "build the reducer life and limit monitor beside the arm datapath (model rnea; docs/monitor.md)",
    Nil,
    _.monitor.enabled
  )

  val monitorExponent = new PerJoint(
    "monitor.exponent",
    "",
    "life exponent p per joint in [1, 10]: 3 strain-wave (Harmonic Drive), 3.3333333333333335 (10/3) cycloidal (RV)",
    Nil,
    _.monitor.exponent
  )

  val monitorRepeatedPeak = new PerJoint(
    "monitor.repeated-peak",
    "N·m",
    "repeated (start/stop) peak limit T_R per joint (urdf: the URDF's <limit effort>)",
    Nil,
    _.monitor.repeatedPeakNm,
    keyword = Some("urdf")
  )

  val monitorMomentaryPeak = new PerJoint(
    "monitor.momentary-peak",
    "N·m",
    "momentary (emergency-stop) peak limit T_M per joint (urdf: momentary-peak-factor x <limit effort>)",
    Nil,
    _.monitor.momentaryPeakNm,
    keyword = Some("urdf")
  )

  val monitorMomentaryPeakFactor = new Real(
    "monitor.momentary-peak-factor",
    "",
    "T_M / <limit effort> when momentary-peak = urdf (catalogues: T_M near 2 T_R; 1.5 is conservative)",
    Nil,
    _.monitor.momentaryPeakFactor
  )

  val monitorGearRatio = new PerJoint(
    "monitor.gear-ratio",
    "",
    "reduction ratio i per joint (input speed = i x joint speed), for the life formula",
    Nil,
    _.monitor.gearRatio
  )

  val monitorSamplePeriod = new Real(
    "monitor.sample-period",
    "s",
    "time between valid samples: dt of the damage sums and the basis of the 20-year overflow proof",
    Nil,
    _.monitor.samplePeriodS
  )

  val monitorHistogramBins = new PerJoint(
    "monitor.histogram-bins",
    "",
    "bins of the |torque| time-at-level histogram per joint (1..256)",
    Nil,
    _.monitor.histogramBins.map(_.toDouble),
    integer = true
  )

  val monitorHistogramBinWidth = new PerJoint(
    "monitor.histogram-bin-width",
    "N·m",
    "histogram bin width per joint (auto: the joint's derived torque range / bins)",
    Nil,
    _.monitor.histogramBinWidthNm,
    keyword = Some("auto")
  )

  val monitorRatedTorque = new PerJoint(
    "monitor.rated-torque",
    "N·m",
    "catalogue rated output torque T_N per joint, for the consumed life (none: no life figure)",
    Nil,
    _.monitor.ratedTorqueNm,
    keyword = Some("none")
  )

  val monitorRatedInputSpeed = new Real(
    "monitor.rated-input-speed",
    "rpm",
    "catalogue rated input speed n_N of the life formula",
    Nil,
    _.monitor.ratedInputSpeedRpm
  )

  val monitorRatedLife = new Real(
    "monitor.rated-life",
    "h",
    "catalogue rated life L_n (L50) at T_N and n_N",
    Nil,
    _.monitor.ratedLifeHours
  )

  /** Every setting, in the order of --help, the docs and a configuration file. */
  val all: Seq[Setting[_]] = Seq(
    robotSource,
    robotTip,
    robotAllowMassless,
    robotM3,
    robotL1,
    robotL2,
    robotL3,
    robotG,
    robotBaseRpy,
    robotMaxVelocity,
    robotMaxAcceleration,
    payloadEnabled,
    payloadMaxMass,
    payloadComRadius,
    payloadMaxGyrationRadius,
    payloadFrame,
    gravityRuntime,
    gravityMaxMagnitude,
    model,
    cordicAngleBits,
    cordicOutputBits,
    cordicIterations,
    cordicGuardBits,
    cordicAngleGuardBits,
    cordicOutputRounding,
    cordicIterationsPerStage,
    cordicArchitecture,
    cordicTableBits,
    datapathVelocityFracBits,
    datapathAccelerationFracBits,
    datapathConstantFracBits,
    datapathInternalFracBits,
    datapathOutputFracBits,
    datapathProductRounding,
    datapathMultiplierLatency,
    datapathMemoryDelayMinCycles,
    datapathRegisteredRoutes,
    datapathReassociate,
    datapathComposeParallelAxes,
    scheduleClocksPerSample,
    scheduleMaxMultipliers,
    scheduleCordicUnits,
    scheduleStorage,
    scheduleConstantMultiplies,
    scheduleListOrder,
    scheduleScheduler,
    scheduleShareRegisters,
    scheduleProductMemories,
    scheduleSinCosMemories,
    scheduleReaderCopies,
    scheduleForwardSlack,
    scheduleAccumulateSlack,
    scheduleListTries,
    scheduleRefinement,
    scheduleAdderUnits,
    deviceName,
    deviceMaxLogicFraction,
    busInterface,
    busTopName,
    numericTargetError,
    monitorEnabled,
    monitorExponent,
    monitorRepeatedPeak,
    monitorMomentaryPeak,
    monitorMomentaryPeakFactor,
    monitorGearRatio,
    monitorSamplePeriod,
    monitorHistogramBins,
    monitorHistogramBinWidth,
    monitorRatedTorque,
    monitorRatedInputSpeed,
    monitorRatedLife
  )

  val byKey: Map[String, Setting[_]] = all.map(s => s.key -> s).toMap

  /** Flag name (without --) -> setting: the key itself and its short aliases. */
  val byFlag: Map[String, Setting[_]] = all.flatMap(s => (s.key +: s.aliases).map(_ -> s)).toMap

  /** Edit distance, for "did you mean" hints. */
  private def distance(a: String, b: String): Int =
    b.indices
      .foldLeft((0 to a.length).toVector) { (prev, j) =>
        a.indices.foldLeft(Vector(j + 1)) { (row, i) =>
          row :+ Seq(prev(i + 1) + 1, row(i) + 1, prev(i) + (if (a(i) == b(j)) 0 else 1)).min
        }
      }
      .last

  /** Keys earlier versions read, and what replaces each. */
  val retired: Map[String, String] = Map(
    "datapath.cordic-units" -> "the scheduler shares CORDIC units now: schedule.cordic-units = 1 with schedule.clocks-per-sample = 3 is the old value 1"
  )

  /**
   * Build parameters from a configuration, complete once `overrides` (flag values, already typed) are laid
   * over it: a key a flag gives need not be in the file, and its value there is not read.
   */
  def toParams(c: Config, source: String, overrides: Seq[Assignment[_]] = Nil): LoadParams = {
    val flagged = overrides.map(_.setting.key).toSet
    val known = all.map(_.key).toSet
    val present = c.entrySet().asScala.map(_.getKey).toSeq.sorted
    present
      .find(retired.contains)
      .foreach(k => throw new InputError(s"$source: key '$k' is retired: ${retired(k)}"))
    present.find(k => !known.contains(k)).foreach { k =>
      val hint = all
        .map(_.key)
        .minByOption(distance(_, k))
        .filter(distance(_, k) <= 3)
        .map(s => s" (did you mean '$s'?)")
        .getOrElse("")
      throw new InputError(s"$source: unknown key '$k'$hint")
    }
    val read = all.filterNot(s => flagged(s.key))
    read
      .find(s => !c.hasPath(s.key))
      .foreach(s => throw new InputError(s"$source: missing key '${s.key}' (${s.help})"))
    read.foreach(_.read(c, source)) // every type error before any bound, in declaration order
    build(
      new Values { def apply[T](s: Setting[T]): T = s.read(c, source) },
      overrides,
      source
    )
  }

  /** `preset` with `overrides` laid over it; the bounds are checked on the result, not on each step. */
  def withOverrides(preset: LoadParams, overrides: Seq[Assignment[_]], source: String): LoadParams =
    build(new Values { def apply[T](s: Setting[T]): T = s.get(preset) }, overrides, source)

  /** Each setting's value, typed: read from a file or taken from a preset. */
  private trait Values { def apply[T](s: Setting[T]): T }

  /**
   * The parameters the settings' values describe, built in one step: the sub-configurations' bounds relate
   * several keys (a URDF robot needs model rnea), so overrides cannot be applied to a checked value one by
   * one.
   */
  private def build(base: Values, overrides: Seq[Assignment[_]], source: String): LoadParams = {
    // The last assignment of a setting wins; `eq` on the setting makes its value's type the setting's.
    def v[T](s: Setting[T]): T =
      overrides.reverseIterator
        .collectFirst { case a if a.setting eq s => a.value.asInstanceOf[T] }
        .getOrElse(base(s))
    // planar3 has three joints: one number stands for all three.
    def ranges(s: Setting[Seq[Double]]) = (v(s), v(robotSource) == RobotParams.planar3) match {
      case (Seq(x), true) => Seq.fill(3)(x)
      case (other, _)     => other
    }
    try
      LoadParams(
        robot = RobotParams(
          m3 = v(robotM3),
          l1 = v(robotL1),
          l2 = v(robotL2),
          l3 = v(robotL3),
          g = v(robotG),
          maxVelocity = ranges(robotMaxVelocity),
          maxAcceleration = ranges(robotMaxAcceleration),
          source = v(robotSource),
          tip = v(robotTip),
          allowMassless = v(robotAllowMassless),
          mounting = v(robotBaseRpy)
        ),
        payload = PayloadSettings(
          enabled = v(payloadEnabled),
          maxMass = v(payloadMaxMass),
          comRadius = v(payloadComRadius),
          maxGyrationRadius = v(payloadMaxGyrationRadius),
          frame = v(payloadFrame)
        ),
        gravity = GravitySettings(runtime = v(gravityRuntime), maxMagnitude = v(gravityMaxMagnitude)),
        model = v(model),
        cordic = CordicParams(
          angleBits = v(cordicAngleBits),
          outputBits = v(cordicOutputBits),
          iterations = v(cordicIterations),
          guardBits = v(cordicGuardBits),
          angleGuardBits = v(cordicAngleGuardBits),
          outputRounding = v(cordicOutputRounding),
          iterationsPerStage = v(cordicIterationsPerStage),
          architecture = v(cordicArchitecture),
          tableBits = v(cordicTableBits)
        ),
        datapath = DatapathParams(
          velocityFracBits = v(datapathVelocityFracBits),
          accelerationFracBits = v(datapathAccelerationFracBits),
          constantFracBits = v(datapathConstantFracBits),
          internalFracBits = v(datapathInternalFracBits),
          outputFracBits = v(datapathOutputFracBits),
          productRounding = v(datapathProductRounding),
          multiplierLatency = v(datapathMultiplierLatency),
          memoryDelayMinCycles = v(datapathMemoryDelayMinCycles),
          registeredRoutes = v(datapathRegisteredRoutes),
          reassociate = v(datapathReassociate),
          composeParallelAxes = v(datapathComposeParallelAxes)
        ),
        targetError = v(numericTargetError),
        device = DeviceTarget(v(deviceName), v(deviceMaxLogicFraction)),
        bus = BusSettings(v(busInterface), v(busTopName)),
        schedule = ScheduleRequest(
          v(scheduleClocksPerSample),
          v(scheduleMaxMultipliers),
          v(scheduleCordicUnits),
          v(scheduleStorage),
          v(scheduleConstantMultiplies),
          v(scheduleListOrder),
          v(scheduleAdderUnits),
          v(scheduleListTries),
          v(scheduleRefinement),
          v(scheduleScheduler),
          v(scheduleShareRegisters),
          v(scheduleReaderCopies),
          v(scheduleForwardSlack),
          v(scheduleAccumulateSlack),
          v(scheduleProductMemories),
          v(scheduleSinCosMemories)
        ),
        monitor = MonitorSettings(
          enabled = v(monitorEnabled),
          exponent = v(monitorExponent),
          repeatedPeakNm = v(monitorRepeatedPeak),
          momentaryPeakNm = v(monitorMomentaryPeak),
          momentaryPeakFactor = v(monitorMomentaryPeakFactor),
          gearRatio = v(monitorGearRatio),
          samplePeriodS = v(monitorSamplePeriod),
          histogramBins = v(monitorHistogramBins).map(_.toInt),
          histogramBinWidthNm = v(monitorHistogramBinWidth),
          ratedTorqueNm = v(monitorRatedTorque),
          ratedInputSpeedRpm = v(monitorRatedInputSpeed),
          ratedLifeHours = v(monitorRatedLife)
        )
      )
    catch {
      case e: IllegalArgumentException =>
        throw new InputError(s"$source: ${e.getMessage.stripPrefix("requirement failed: ")}")
    }
  }

  /** The settings table of docs/configuration.md (SettingsDocSpec checks the file carries it). */
  def markdownTable: String =
    ("| key | flag | type | unit | default | meaning |" +: "| --- | --- | --- | --- | --- | --- |" +: all
      .map { s =>
        val flags = (s.key +: s.aliases.filterNot(_ == s.key)).map(f => s"`--$f`").mkString(" ")
        s"| `${s.key}` | $flags | ${s.typeName.replace("|", " \\| ")} | ${s.unit} | ${s.render(LoadParams.default)} | ${s.help} |"
      }).mkString("\n")

  /** Every setting's value, one `key = value` line each: what a design is, without the help texts. */
  def values(p: LoadParams): String = all.map(s => s"${s.key} = ${s.render(p)}").mkString("\n")

  /** A complete HOCON file for `p`, grouped by section, with units and meanings as comments. */
  def render(p: LoadParams, header: Seq[String]): String = {
    val order =
      Seq(
        "",
        "robot",
        "payload",
        "gravity",
        "cordic",
        "datapath",
        "numeric",
        "schedule",
        "device",
        "bus",
        "monitor"
      )
    val body = order.flatMap { section =>
      val settings = all.filter(s => (if (s.key.contains('.')) s.key.takeWhile(_ != '.') else "") == section)
      if (settings.isEmpty) Nil
      else {
        def line(s: Setting[_], indent: String) = {
          val name = if (section.isEmpty) s.key else s.key.stripPrefix(section + ".")
          val unit = if (s.unit.nonEmpty) s" [${s.unit}]" else ""
          s"$indent$name = ${s.render(p)}  # ${s.help}$unit"
        }
        if (section.isEmpty) settings.map(line(_, ""))
        else (s"$section {" +: settings.map(line(_, "  "))) :+ "}"
      }
    }
    (header.map("# " + _) ++ body).mkString("", "\n", "\n")
  }
}
