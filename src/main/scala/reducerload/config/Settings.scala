package reducerload.config

import com.typesafe.config.{Config, ConfigException, ConfigValueType}
import reducerload.cordic.{CordicArchitecture, CordicParams}
import reducerload.fixedpoint.Rounding
import reducerload.load.LoadModel
import reducerload.robot.RobotParams
import reducerload.util.InputError

import scala.jdk.CollectionConverters._

/** One configuration key: its HOCON path, unit, meaning, type, and where it lives in [[LoadParams]]. */
sealed abstract class Setting(val key: String, val unit: String, val help: String, val aliases: Seq[String]) {

  /** The value in `p`, as HOCON text. */
  def render(p: LoadParams): String

  /** Read and type-check the value at `key`; `source` names the file or flag for errors. */
  def read(c: Config, source: String): Any

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

  final class Real(
      key: String,
      unit: String,
      help: String,
      aliases: Seq[String],
      val get: LoadParams => Double
  ) extends Setting(key, unit, help, aliases) {
    def render(p: LoadParams): String = get(p).toString
    def typeName = "number"
    def read(c: Config, source: String): Any =
      if (c.getValue(key).valueType() != ConfigValueType.NUMBER) wrongType(source, "a number", c)
      else c.getDouble(key)
  }

  final class Natural(
      key: String,
      unit: String,
      help: String,
      aliases: Seq[String],
      val get: LoadParams => Int
  ) extends Setting(key, unit, help, aliases) {
    def render(p: LoadParams): String = get(p).toString
    def typeName = "integer"
    def read(c: Config, source: String): Any = {
      val ok = c.getValue(key).valueType() == ConfigValueType.NUMBER && {
        val d = c.getDouble(key); d == math.rint(d) && math.abs(d) < 1e9
      }
      if (!ok) wrongType(source, "an integer", c) else c.getDouble(key).toInt
    }
  }

  final class Choice(
      key: String,
      unit: String,
      help: String,
      aliases: Seq[String],
      val choices: Seq[String],
      val get: LoadParams => String
  ) extends Setting(key, unit, help, aliases) {
    def render(p: LoadParams): String = get(p)
    def typeName: String = choices.mkString("|")
    def read(c: Config, source: String): Any = {
      if (c.getValue(key).valueType() != ConfigValueType.STRING)
        wrongType(source, s"one of ${choices.mkString(", ")}", c)
      val s = c.getString(key)
      if (!choices.contains(s))
        throw new InputError(s"$source: key '$key' must be one of ${choices.mkString(", ")}, got '$s'")
      s
    }
  }

  /** A string (a file path or a name); `allowEmpty` for optional values. */
  final class Text(
      key: String,
      unit: String,
      help: String,
      aliases: Seq[String],
      val get: LoadParams => String
  ) extends Setting(key, unit, help, aliases) {
    def render(p: LoadParams): String = com.typesafe.config.ConfigValueFactory.fromAnyRef(get(p)).render()
    def typeName = "string"
    def read(c: Config, source: String): Any =
      if (c.getValue(key).valueType() != ConfigValueType.STRING) wrongType(source, "a string", c)
      else c.getString(key)
  }

  /** On or off (HOCON true/false). */
  final class Switch(
      key: String,
      unit: String,
      help: String,
      aliases: Seq[String],
      val get: LoadParams => Boolean
  ) extends Setting(key, unit, help, aliases) {
    def render(p: LoadParams): String = get(p).toString
    def typeName = "true|false"
    def read(c: Config, source: String): Any =
      if (c.getValue(key).valueType() != ConfigValueType.BOOLEAN) wrongType(source, "true or false", c)
      else c.getBoolean(key)
  }

  /** A whole number, or `keyword` for a derived or absent value (read as None). */
  final class Count(
      key: String,
      unit: String,
      help: String,
      aliases: Seq[String],
      keyword: String,
      val get: LoadParams => Option[Int]
  ) extends Setting(key, unit, help, aliases) {
    def render(p: LoadParams): String = get(p).fold(keyword)(_.toString)
    def typeName = s"integer or $keyword"
    def read(c: Config, source: String): Any = c.getValue(key).valueType() match {
      case ConfigValueType.STRING if c.getString(key) == keyword => Option.empty[Int]
      case ConfigValueType.NUMBER if { val d = c.getDouble(key); d == math.rint(d) && math.abs(d) < 1e9 } =>
        Some(c.getDouble(key).toInt)
      case _ => wrongType(source, s"an integer or $keyword", c)
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
      val get: LoadParams => Seq[Double],
      keyword: Option[String] = None,
      integer: Boolean = false
  ) extends Setting(key, unit, help, aliases) {
    private def show(x: Double): String = if (integer) x.toLong.toString else x.toString
    def render(p: LoadParams): String = get(p) match {
      case Seq()  => keyword.getOrElse("[]")
      case Seq(x) => show(x)
      case values => values.map(show).mkString("[", ", ", "]")
    }
    private val kind = if (integer) "integer" else "number"
    def typeName: String = s"$kind or [n1, ..., nN]" + keyword.fold("")(k => s" or $k")
    def read(c: Config, source: String): Any = {
      def checked(xs: Seq[Double]): Seq[Double] =
        if (integer && xs.exists(x => x != math.rint(x) || math.abs(x) >= 1e9))
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

/** Every key of a configuration, with units and defaults: the single source of --help and the docs table. */
object Settings {
  import Setting._
  private val roundings = Rounding.all.map(_.name)

  val all: Seq[Setting] = Seq(
    new Text(
      "robot.source",
      "",
      "planar3 (the built-in planar arm below) or the path of a URDF file",
      Seq("robot"),
      _.robot.source
    ),
    new Text(
      "robot.tip",
      "",
      "URDF link that ends the chain (empty: the only leaf)",
      Seq("tip"),
      _.robot.tip
    ),
    new Real("robot.m3", "kg", "planar3: point mass at the end of link 3", Seq("m3"), _.robot.m3),
    new Real("robot.l1", "m", "planar3: length of link 1", Seq("l1"), _.robot.l1),
    new Real("robot.l2", "m", "planar3: length of link 2", Seq("l2"), _.robot.l2),
    new Real("robot.l3", "m", "planar3: length of link 3", Seq("l3"), _.robot.l3),
    new Real(
      "robot.g",
      "m/s^2",
      "planar3: gravitational acceleration (t1 = 0 points link 1 down; a URDF robot has 9.81 along -z)",
      Seq("g"),
      _.robot.g
    ),
    new PerJoint(
      "robot.max-velocity",
      "rad/s",
      "declared max |velocity| per joint (urdf: the URDF's <limit velocity>)",
      Seq("max-velocity"),
      _.robot.maxVelocity,
      keyword = Some("urdf")
    ),
    new PerJoint(
      "robot.max-acceleration",
      "rad/s^2",
      "declared max |acceleration| per joint (a URDF has none: declare it)",
      Seq("max-acceleration"),
      _.robot.maxAcceleration
    ),
    new Choice(
      "model",
      "",
      "exact (SPEC.md tau3) or paper (equation (6) as published): planar3's joint 3; rnea: every joint of any robot",
      Nil,
      LoadModel.all.map(_.name),
      _.model.name
    ),
    new Natural(
      "cordic.angle-bits",
      "bits",
      "binary-angle width (full turn = 2^bits)",
      Nil,
      _.cordic.angleBits
    ),
    new Natural("cordic.output-bits", "bits", "sin/cos width, format Q1.(bits-2)", Nil, _.cordic.outputBits),
    new Natural(
      "cordic.iterations",
      "",
      "CORDIC micro-rotations (iteration 0 folded)",
      Nil,
      _.cordic.iterations
    ),
    new Natural("cordic.guard-bits", "bits", "extra fraction bits in x, y", Nil, _.cordic.guardBits),
    new Natural(
      "cordic.angle-guard-bits",
      "bits",
      "extra fraction bits in the angle accumulator",
      Nil,
      _.cordic.angleGuardBits
    ),
    new Choice(
      "cordic.output-rounding",
      "",
      "sin/cos output rounding",
      Nil,
      roundings,
      _.cordic.outputRounding.name
    ),
    new Natural(
      "cordic.iterations-per-stage",
      "",
      "micro-rotations between pipeline registers",
      Nil,
      _.cordic.iterationsPerStage
    ),
    new Choice(
      "cordic.architecture",
      "",
      "classic (shift-add only) or residual (shift-add, then one multiply-based rotation)",
      Nil,
      CordicArchitecture.all.map(_.name),
      _.cordic.architecture.name
    ),
    new Natural(
      "cordic.table-bits",
      "bits",
      "start-vector table (ROM) of 2^bits entries replacing iterations 0..bits (0: none)",
      Nil,
      _.cordic.tableBits
    ),
    new Natural(
      "datapath.velocity-frac-bits",
      "bits",
      "fraction bits of velocity inputs (rad/s)",
      Nil,
      _.velocityFracBits
    ),
    new Natural(
      "datapath.acceleration-frac-bits",
      "bits",
      "fraction bits of acceleration inputs (rad/s^2)",
      Nil,
      _.accelerationFracBits
    ),
    new Natural(
      "datapath.constant-frac-bits",
      "bits",
      "fraction bits of folded robot constants",
      Nil,
      _.constantFracBits
    ),
    new Natural(
      "datapath.internal-frac-bits",
      "bits",
      "fraction bits of products and sums",
      Nil,
      _.internalFracBits
    ),
    new Natural(
      "datapath.output-frac-bits",
      "bits",
      "fraction bits of the load output (N·m)",
      Nil,
      _.outputFracBits
    ),
    new Choice(
      "datapath.product-rounding",
      "",
      "rounding of products to internal-frac-bits",
      Nil,
      roundings,
      _.productRounding.name
    ),
    new Natural(
      "datapath.multiplier-latency",
      "cycles",
      "registers after each multiplier",
      Nil,
      _.multiplierLatency
    ),
    new Natural(
      "datapath.memory-delay-min-cycles",
      "cycles",
      "delays this long or longer use block RAM (0: registers only)",
      Nil,
      _.memoryDelayMinCycles
    ),
    new Count(
      "schedule.clocks-per-sample",
      "clocks",
      "clocks between samples (the initiation interval; auto: the fewest the multiplier budget allows)",
      Seq("clocks-per-sample"),
      "auto",
      _.schedule.clocksPerSample
    ),
    new Count(
      "schedule.max-multipliers",
      "18x18 blocks",
      "18x18 multiplier blocks the datapath may use, its CORDIC units' included (none: no budget; a monitor's come on top)",
      Seq("max-multipliers"),
      "none",
      _.schedule.maxMultipliers
    ),
    new Count(
      "schedule.cordic-units",
      "",
      "sin/cos units shared by the angles (auto: the fewest that keep clocks-per-sample)",
      Nil,
      "auto",
      _.schedule.cordicUnits
    ),
    new Choice(
      "schedule.storage",
      "",
      "clocks-per-sample >= 2: registers (every value its own registers, operands multiplexed) or memory " +
        "(values in block-RAM banks read by address, adders shared too: far fewer logic elements)",
      Nil,
      reducerload.graph.Storage.all.map(_.name),
      _.schedule.storage.name
    ),
    new Choice(
      "schedule.constant-multiplies",
      "",
      "multiplies by a folded robot constant: blocks (on the 18x18 multiplier units) or shift-add " +
        "(the constant's signed digits summed in logic elements: no multiplier block, more logic; storage registers only)",
      Nil,
      reducerload.graph.ConstantMultiplies.all.map(_.name),
      _.schedule.constantMultiplies.name
    ),
    new Choice(
      "schedule.list-order",
      "",
      "storage memory: the list scheduler's order, by-height (each operation, critical path first, at its " +
        "first free cycle) or by-cycle (each cycle's ready operations, critical path first); auto: both, the shorter latency kept",
      Nil,
      "auto" +: reducerload.graph.ListOrder.all.map(_.name),
      _.schedule.listOrder.fold("auto")(_.name)
    ),
    new Natural(
      "schedule.list-tries",
      "",
      "storage memory: by-height schedules tried, the first in the plain order, the others with each " +
        "priority raised by 0 or 1 (seeded, so the same every run); the shortest kept",
      Nil,
      _.schedule.listTries
    ),
    new Count(
      "schedule.adder-units",
      "",
      "storage memory: shared adder units (auto: the fewest that take every addition; " +
        "more cost logic elements and shorten the latency)",
      Nil,
      "auto",
      _.schedule.adderUnits
    ),
    new PerJoint(
      "numeric.target-error",
      "N·m",
      "derived error bound to meet per torque; the datapath's fraction bits become the fewest that meet it " +
        "(none: as set above)",
      Seq("target-error"),
      _.targetError,
      keyword = Some("none")
    ),
    new Switch(
      "monitor.enabled",
      "",
      "build the reducer life and limit monitor beside the arm datapath (model rnea; docs/monitor.md)",
      Nil,
      _.monitor.enabled
    ),
    new PerJoint(
      "monitor.exponent",
      "",
      "life exponent p per joint in [1, 10]: 3 strain-wave (Harmonic Drive), 3.3333333333333335 (10/3) cycloidal (RV)",
      Nil,
      _.monitor.exponent
    ),
    new PerJoint(
      "monitor.repeated-peak",
      "N·m",
      "repeated (start/stop) peak limit T_R per joint (urdf: the URDF's <limit effort>)",
      Nil,
      _.monitor.repeatedPeakNm,
      keyword = Some("urdf")
    ),
    new PerJoint(
      "monitor.momentary-peak",
      "N·m",
      "momentary (emergency-stop) peak limit T_M per joint (urdf: momentary-peak-factor x <limit effort>)",
      Nil,
      _.monitor.momentaryPeakNm,
      keyword = Some("urdf")
    ),
    new Real(
      "monitor.momentary-peak-factor",
      "",
      "T_M / <limit effort> when momentary-peak = urdf (catalogues: T_M near 2 T_R; 1.5 is conservative)",
      Nil,
      _.monitor.momentaryPeakFactor
    ),
    new PerJoint(
      "monitor.gear-ratio",
      "",
      "reduction ratio i per joint (input speed = i x joint speed), for the life formula",
      Nil,
      _.monitor.gearRatio
    ),
    new Real(
      "monitor.sample-period",
      "s",
      "time between valid samples: dt of the damage sums and the basis of the 20-year overflow proof",
      Nil,
      _.monitor.samplePeriodS
    ),
    new PerJoint(
      "monitor.histogram-bins",
      "",
      "bins of the |torque| time-at-level histogram per joint (1..256)",
      Nil,
      _.monitor.histogramBins.map(_.toDouble),
      integer = true
    ),
    new PerJoint(
      "monitor.histogram-bin-width",
      "N·m",
      "histogram bin width per joint (auto: the joint's derived torque range / bins)",
      Nil,
      _.monitor.histogramBinWidthNm,
      keyword = Some("auto")
    ),
    new PerJoint(
      "monitor.rated-torque",
      "N·m",
      "catalogue rated output torque T_N per joint, for the consumed life (none: no life figure)",
      Nil,
      _.monitor.ratedTorqueNm,
      keyword = Some("none")
    ),
    new Real(
      "monitor.rated-input-speed",
      "rpm",
      "catalogue rated input speed n_N of the life formula",
      Nil,
      _.monitor.ratedInputSpeedRpm
    ),
    new Real(
      "monitor.rated-life",
      "h",
      "catalogue rated life L_n (L50) at T_N and n_N",
      Nil,
      _.monitor.ratedLifeHours
    )
  )

  val byKey: Map[String, Setting] = all.map(s => s.key -> s).toMap

  /** Flag name (without --) -> setting: the key itself and its short aliases. */
  val byFlag: Map[String, Setting] = all.flatMap(s => (s.key +: s.aliases).map(_ -> s)).toMap

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

  /** Build parameters from a complete, type-checked configuration. */
  def toParams(c: Config, source: String): LoadParams = {
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
    all
      .find(s => !c.hasPath(s.key))
      .foreach(s => throw new InputError(s"$source: missing key '${s.key}' (${s.help})"))
    val v: Map[String, Any] = all.map(s => s.key -> s.read(c, source)).toMap
    def real(k: String) = v(k).asInstanceOf[Double]
    def bool(k: String) = v(k).asInstanceOf[Boolean]
    def int(k: String) = v(k).asInstanceOf[Int]
    def str(k: String) = v(k).asInstanceOf[String]
    def joints(k: String) = v(k).asInstanceOf[Seq[Double]]
    def count(k: String) = v(k).asInstanceOf[Option[Int]]
    val planar = str("robot.source") == RobotParams.planar3
    def ranges(k: String) = joints(k) match { // planar3 has three joints: one number stands for all three
      case Seq(x) if planar => Seq.fill(3)(x)
      case other            => other
    }
    def rounding(k: String) = Rounding.parse(str(k)).get
    try {
      val p = LoadParams(
        robot = RobotParams(
          m3 = real("robot.m3"),
          l1 = real("robot.l1"),
          l2 = real("robot.l2"),
          l3 = real("robot.l3"),
          g = real("robot.g"),
          maxVelocity = ranges("robot.max-velocity"),
          maxAcceleration = ranges("robot.max-acceleration"),
          source = str("robot.source"),
          tip = str("robot.tip")
        ),
        model = LoadModel.parse(str("model")).get,
        cordic = CordicParams(
          angleBits = int("cordic.angle-bits"),
          outputBits = int("cordic.output-bits"),
          iterations = int("cordic.iterations"),
          guardBits = int("cordic.guard-bits"),
          angleGuardBits = int("cordic.angle-guard-bits"),
          outputRounding = rounding("cordic.output-rounding"),
          iterationsPerStage = int("cordic.iterations-per-stage"),
          architecture = CordicArchitecture.parse(str("cordic.architecture")).get,
          tableBits = int("cordic.table-bits")
        ),
        velocityFracBits = int("datapath.velocity-frac-bits"),
        accelerationFracBits = int("datapath.acceleration-frac-bits"),
        constantFracBits = int("datapath.constant-frac-bits"),
        internalFracBits = int("datapath.internal-frac-bits"),
        outputFracBits = int("datapath.output-frac-bits"),
        productRounding = rounding("datapath.product-rounding"),
        multiplierLatency = int("datapath.multiplier-latency"),
        memoryDelayMinCycles = int("datapath.memory-delay-min-cycles"),
        targetError = joints("numeric.target-error"),
        schedule = reducerload.graph.ScheduleRequest(
          count("schedule.clocks-per-sample"),
          count("schedule.max-multipliers"),
          count("schedule.cordic-units"),
          reducerload.graph.Storage.all.find(_.name == str("schedule.storage")).get,
          reducerload.graph.ConstantMultiplies.all.find(_.name == str("schedule.constant-multiplies")).get,
          reducerload.graph.ListOrder.all.find(_.name == str("schedule.list-order")),
          count("schedule.adder-units"),
          int("schedule.list-tries")
        ),
        monitor = MonitorSettings(
          enabled = bool("monitor.enabled"),
          exponent = joints("monitor.exponent"),
          repeatedPeakNm = joints("monitor.repeated-peak"),
          momentaryPeakNm = joints("monitor.momentary-peak"),
          momentaryPeakFactor = real("monitor.momentary-peak-factor"),
          gearRatio = joints("monitor.gear-ratio"),
          samplePeriodS = real("monitor.sample-period"),
          histogramBins = joints("monitor.histogram-bins").map(_.toInt),
          histogramBinWidthNm = joints("monitor.histogram-bin-width"),
          ratedTorqueNm = joints("monitor.rated-torque"),
          ratedInputSpeedRpm = real("monitor.rated-input-speed"),
          ratedLifeHours = real("monitor.rated-life")
        )
      )
      p
    } catch {
      case e: IllegalArgumentException =>
        throw new InputError(s"$source: ${e.getMessage.stripPrefix("requirement failed: ")}")
    }
  }

  /** The settings table of the README (tested to match). */
  def markdownTable: String =
    ("| key | flag | type | unit | default | meaning |" +: "| --- | --- | --- | --- | --- | --- |" +: all
      .map { s =>
        val flags = (s.key +: s.aliases.filterNot(_ == s.key)).map(f => s"`--$f`").mkString(" ")
        s"| `${s.key}` | $flags | ${s.typeName.replace("|", " \\| ")} | ${s.unit} | ${s.render(LoadParams.default)} | ${s.help} |"
      }).mkString("\n")

  /** A complete HOCON file for `p`, grouped by section, with units and meanings as comments. */
  def render(p: LoadParams, header: Seq[String]): String = {
    val order = Seq("", "robot", "cordic", "datapath", "numeric", "schedule", "monitor")
    val body = order.flatMap { section =>
      val settings = all.filter(s => (if (s.key.contains('.')) s.key.takeWhile(_ != '.') else "") == section)
      if (settings.isEmpty) Nil
      else {
        def line(s: Setting, indent: String) = {
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
