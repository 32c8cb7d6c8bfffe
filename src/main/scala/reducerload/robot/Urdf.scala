package reducerload.robot

import reducerload.trace.TraceCsv
import reducerload.util.{InputError, InputFile, Warning}

import java.nio.ByteBuffer
import java.nio.charset.{CharacterCodingException, CodingErrorAction, StandardCharsets}
import java.nio.file.{Files, Path}
import javax.xml.parsers.SAXParserFactory
import scala.collection.mutable
import scala.xml.{Node, SAXParseException, XML}

/**
 * Reads a URDF robot description into the serial chain from its root link to a tip link, with the semantics
 * of Pinocchio's `buildModelFromUrdf` followed by `buildReducedModel` (the reference of the golden traces):
 * fixed joints fold into the next moving joint's origin, and everything off the chain (side branches,
 * children of the tip) is locked at q = 0 and its mass merged into the chain link it hangs off. Every problem
 * in the file is an [[InputError]] of one line "<file>: <element>: <problem>".
 *
 * Missing mass: a link that a joint moves (the child of a revolute, continuous or prismatic joint, on the
 * chain or locked off it) with no `<inertial>` is taken as massless with a [[Warning]] naming it and where
 * its joint's mass comes from. Links fixed to another link with no `<inertial>` are frames (tool0, flange,
 * ee_link) and stay quiet. Joints that move no mass at all (every link from theirs to the tip massless: the
 * torque is identically zero) are refused unless `allowMassless` (the setting `robot.allow-massless`), then
 * warned about.
 */
object Urdf {
  def read(path: Path, tip: Option[String], allowMassless: Boolean = false): SerialChain = {
    val source = path.toString
    InputFile.check(path, source)
    val text =
      try
        StandardCharsets.UTF_8
          .newDecoder()
          .onMalformedInput(CodingErrorAction.REPORT)
          .decode(ByteBuffer.wrap(Files.readAllBytes(path)))
          .toString
      catch {
        case _: CharacterCodingException => throw new InputError(s"$source: not a text file (invalid UTF-8)")
      }
    parse(source, text, tip, allowMassless)
  }

  def parse(
      source: String,
      xmlText: String,
      tip: Option[String],
      allowMassless: Boolean = false
  ): SerialChain =
    new UrdfChainBuilder(source, new UrdfParser(source).robot(xmlText)).chain(tip, allowMassless)

  /**
   * Largest mass (kg) and coordinate (m) a link may have: beyond any arm (a 10 t link, a 100 m reach), and
   * within what the derived formats can hold; an inertia entry is at most their mass times length squared.
   */
  val maxMass: Double = 1e4
  val maxLength: Double = 100.0
  val maxInertia: Double = maxMass * maxLength * maxLength

  /** Characters of the longest number a URDF attribute may hold (every double fits in far fewer). */
  val longestNumber: Int = 100

  /** The setting that accepts joints moving no mass, as the refusal names it. */
  val allowMasslessSetting: String = "robot.allow-massless"

  /**
   * Tolerance of the inertia plausibility checks: relative to the largest principal moment, plus an absolute
   * floor for tensors that are zero up to rounding (iCub writes 2.4e-35 entries).
   */
  val inertiaRelativeTolerance: Double = 1e-6
  val inertiaAbsoluteTolerance: Double = 1e-12

  /**
   * "<file>: <element>: <problem>" on one line, whatever the names in the file contain, and cut short: a name
   * may be thousands of characters long.
   */
  private[robot] def error(source: String, element: String, problem: String): InputError = {
    val line = s"$source: $element: $problem".replaceAll("\\s+", " ").trim
    new InputError(if (line.length > maxMessage) line.take(maxMessage) + " [...]" else line)
  }

  /** Characters of an error line beyond which it is cut. */
  val maxMessage: Int = 600
}

/** One URDF link: its mass properties in the link frame, if it has an `<inertial>`. */
private final case class UrdfLink(name: String, inertial: Option[RigidBody])

/** One URDF joint; `motion` is None for a fixed joint. */
private final case class UrdfJoint(
    name: String,
    motion: Option[JointKind],
    parent: String,
    child: String,
    origin: Transform,
    axis: Vec3,
    velocityLimit: Option[Double],
    effortLimit: Option[Double],
    mimic: Boolean
) {
  def label: String = s"joint '$name'"
}

private final case class UrdfRobot(name: String, links: IndexedSeq[UrdfLink], joints: IndexedSeq[UrdfJoint]) {
  def label: String = s"robot '$name'"
}

/** XML to links and joints, checking every element and number it reads. */
private final class UrdfParser(source: String) {
  private def fail(element: String, problem: String): Nothing = throw Urdf.error(source, element, problem)

  /**
   * External entities, DTDs and XInclude off: a robot file must not make the reader open other files or URLs.
   */
  private def secureParser = {
    val factory = SAXParserFactory.newInstance()
    factory.setFeature("http://javax.xml.XMLConstants/feature/secure-processing", true)
    factory.setFeature("http://apache.org/xml/features/disallow-doctype-decl", true)
    factory.setFeature("http://apache.org/xml/features/nonvalidating/load-external-dtd", false)
    factory.setFeature("http://xml.org/sax/features/external-general-entities", false)
    factory.setFeature("http://xml.org/sax/features/external-parameter-entities", false)
    factory.setXIncludeAware(false)
    factory.setNamespaceAware(false)
    factory.newSAXParser()
  }

  def robot(xmlText: String): UrdfRobot = {
    val root =
      try XML.withSAXParser(secureParser).loadString(xmlText)
      catch { case e: SAXParseException => fail("XML", s"line ${e.getLineNumber}: ${e.getMessage}") }
    if (root.label != "robot") fail(s"<${root.label}>", "not a URDF file (the top element must be <robot>)")
    val name = requiredName(root, "<robot>")
    UrdfRobot(
      name,
      (root \ "link").zipWithIndex.map { case (n, i) => link(n, i) }.toIndexedSeq,
      (root \ "joint").zipWithIndex.map { case (n, i) => joint(n, i) }.toIndexedSeq
    )
  }

  private def requiredName(node: Node, element: String): String =
    node
      .attribute("name")
      .map(_.text.trim)
      .filter(_.nonEmpty)
      .getOrElse(fail(element, "missing attribute 'name'"))

  private def attribute(node: Node, key: String): Option[String] = node.attribute(key).map(_.text)

  /** At most one child element `label` (URDF allows one of each). */
  private def single(node: Node, element: String, label: String): Option[Node] = (node \ label) match {
    case Seq()  => None
    case Seq(n) => Some(n)
    case _      => fail(element, s"more than one <$label>")
  }

  private def numbers(text: String, element: String, what: String, count: Int): Seq[Double] = {
    val cells = text.trim.split("\\s+").toSeq.filter(_.nonEmpty)
    // No number is this long; a long cell is not handed to the number pattern, whose time grows with it.
    val values = cells.filter(_.length <= Urdf.longestNumber).flatMap(TraceCsv.parseNumber)
    if (cells.size != count || values.size != count) {
      val expected = if (count == 1) "a finite number" else s"$count finite numbers"
      fail(element, s"$what '${text.trim.take(60)}' is not $expected")
    }
    values
  }

  private def number(node: Node, element: String, tag: String, key: String): Double =
    numbers(
      attribute(node, key).getOrElse(fail(element, s"<$tag> has no attribute '$key'")),
      element,
      s"<$tag $key>",
      1
    ).head

  private def optionalNumber(node: Node, element: String, tag: String, key: String): Option[Double] =
    attribute(node, key).map(t => numbers(t, element, s"<$tag $key>", 1).head)

  private def vector(node: Option[Node], element: String, tag: String, key: String, default: Vec3): Vec3 =
    node.flatMap(attribute(_, key)).map(t => Vec3(numbers(t, element, s"<$tag $key>", 3))).getOrElse(default)

  private def atMost(value: Double, limit: Double, element: String, what: String, unit: String): Double =
    if (math.abs(value) > limit)
      fail(element, s"$what $value $unit is beyond $limit $unit: not a robot arm's")
    else value

  /**
   * `<origin xyz rpy>` (zeros when absent): the child frame in the parent frame, R = Rz(yaw) Ry(pitch)
   * Rx(roll).
   */
  private def origin(node: Node, element: String): Transform = {
    val o = single(node, element, "origin")
    val rpy = vector(o, element, "origin", "rpy", Vec3.zero)
    val xyz = vector(o, element, "origin", "xyz", Vec3.zero)
    xyz.toSeq.foreach(atMost(_, Urdf.maxLength, element, "<origin xyz>", "m"))
    Transform(Mat3.rpy(rpy.x, rpy.y, rpy.z), xyz)
  }

  private def link(node: Node, index: Int): UrdfLink = {
    val name = requiredName(node, s"link #${index + 1}")
    val element = s"link '$name'"
    UrdfLink(
      name,
      single(node, element, "inertial").map { inertial =>
        val frame = origin(inertial, element)
        val mass = atMost(
          number(
            single(inertial, element, "mass").getOrElse(fail(element, "<inertial> has no <mass>")),
            element,
            "mass",
            "value"
          ),
          Urdf.maxMass,
          element,
          "<mass value>",
          "kg"
        )
        val i = single(inertial, element, "inertia").getOrElse(fail(element, "<inertial> has no <inertia>"))
        def entry(key: String) =
          atMost(number(i, element, "inertia", key), Urdf.maxInertia, element, s"<inertia $key>", "kg m^2")
        val tensor =
          Mat3.symmetric(entry("ixx"), entry("ixy"), entry("ixz"), entry("iyy"), entry("iyz"), entry("izz"))
        // About the centre of mass in the inertial frame; into the link frame: com = xyz, I' = R I R^T.
        RigidBody(mass, Vec3.zero, tensor).transformed(frame)
      }
    )
  }

  private def joint(node: Node, index: Int): UrdfJoint = {
    val name = requiredName(node, s"joint #${index + 1}")
    val element = s"joint '$name'"
    val motion = attribute(node, "type").getOrElse(fail(element, "missing attribute 'type'")) match {
      case "revolute"   => Some(JointKind.Revolute)
      case "continuous" => Some(JointKind.Continuous)
      case "prismatic"  => Some(JointKind.Prismatic)
      case "fixed"      => None
      case t @ ("floating" | "planar") =>
        fail(element, s"$t joints are not supported (a serial arm with a fixed base is)")
      case t => fail(element, s"unknown joint type '$t' (revolute, continuous, prismatic, fixed)")
    }
    def linkOf(tag: String) = single(node, element, tag)
      .flatMap(attribute(_, "link"))
      .map(_.trim)
      .filter(_.nonEmpty)
      .getOrElse(fail(element, s"missing <$tag link=...>"))
    val rawAxis = vector(single(node, element, "axis"), element, "axis", "xyz", Vec3(1, 0, 0))
    // Scaled by its largest component first: the norm of (0, 0, 1.7e308) overflows, that of 1e-320s underflows.
    val largest = rawAxis.toSeq.map(math.abs).max
    if (motion.isDefined && largest == 0) fail(element, "zero <axis xyz>")
    val scaled =
      if (largest == 0) rawAxis else Vec3(rawAxis.x / largest, rawAxis.y / largest, rawAxis.z / largest)
    val limit = single(node, element, "limit")
    def nonNegativeLimit(key: String) = limit.flatMap(optionalNumber(_, element, "limit", key)).map { v =>
      if (v < 0) fail(element, s"negative <limit $key> $v") else v
    }
    UrdfJoint(
      name,
      motion,
      linkOf("parent"),
      linkOf("child"),
      origin(node, element),
      if (motion.isEmpty) rawAxis else scaled * (1 / scaled.norm), // a fixed joint's axis means nothing
      nonNegativeLimit("velocity"),
      nonNegativeLimit("effort"),
      single(node, element, "mimic").isDefined
    )
  }
}

/** Is a body physically possible? (Checked on the links whose mass the chain carries.) */
private object UrdfInertia {
  def problem(body: RigidBody): Option[String] = {
    val moments = principalMoments(body.inertia)
    def show(vs: Seq[Double]) = vs.map(v => f"$v%.6g").mkString(", ")
    val tolerance = Urdf.inertiaRelativeTolerance * moments.map(math.abs).max + Urdf.inertiaAbsoluteTolerance
    if (body.mass < 0) Some(s"negative mass ${body.mass}")
    else if (moments.head < -tolerance)
      Some(s"inertia is not positive semi-definite (principal moments ${show(moments)})")
    // A real body's principal moments satisfy I3 <= I1 + I2 (sorted ascending).
    else if (moments(2) > moments(0) + moments(1) + tolerance)
      Some(
        s"principal moments ${show(moments)} violate the triangle inequality (the largest " +
          s"exceeds the sum of the others)"
      )
    else None
  }

  /** Eigenvalues of a symmetric 3x3 matrix, ascending (closed form, Smith 1961). */
  def principalMoments(a: Mat3): Seq[Double] = {
    val offDiagonal = a(0, 1) * a(0, 1) + a(0, 2) * a(0, 2) + a(1, 2) * a(1, 2)
    if (offDiagonal == 0) Seq(a(0, 0), a(1, 1), a(2, 2)).sorted
    else {
      val q = (a(0, 0) + a(1, 1) + a(2, 2)) / 3
      val p = math.sqrt(((0 until 3).map(i => math.pow(a(i, i) - q, 2)).sum + 2 * offDiagonal) / 6)
      val b = (a - Mat3.identity.scale(q)).scale(1 / p)
      val det = b(0, 0) * (b(1, 1) * b(2, 2) - b(1, 2) * b(2, 1)) - b(0, 1) * (b(1, 0) * b(2, 2) - b(
        1,
        2
      ) * b(2, 0)) +
        b(0, 2) * (b(1, 0) * b(2, 1) - b(1, 1) * b(2, 0))
      val phi = math.acos(math.max(-1.0, math.min(1.0, det / 2))) / 3
      val largest = q + 2 * p * math.cos(phi)
      val smallest = q + 2 * p * math.cos(phi + 2 * math.Pi / 3)
      Seq(smallest, 3 * q - largest - smallest, largest)
    }
  }
}

/**
 * Where a link sits at q = 0: in the frame of the moving chain joint that carries it (`carrier`, an index
 * into the chain), or in the root frame (None: fixed to the base).
 */
private final case class Placement(carrier: Option[Int], pose: Transform)

/** Links and joints to the serial chain from the root link to the tip link. */
private final class UrdfChainBuilder(source: String, robot: UrdfRobot) {
  private def fail(element: String, problem: String): Nothing = throw Urdf.error(source, element, problem)

  /** Names for a message: the first few, so that a file of thousands of links still gives one short line. */
  private def few(names: Seq[String], show: String => String): String = {
    val shown = names.take(8).map(n => show(n.take(60))).mkString(", ")
    if (names.size > 8) s"$shown and ${names.size - 8} more" else shown
  }
  private def quoted(names: Seq[String]): String = few(names, n => s"'$n'")

  private val linkNames = robot.links.map(_.name)
  duplicate(linkNames).foreach(n => fail(s"link '$n'", "defined twice"))
  duplicate(robot.joints.map(_.name)).foreach(n => fail(s"joint '$n'", "defined twice"))
  private val linkSet = linkNames.toSet
  robot.joints.foreach { j =>
    Seq("parent" -> j.parent, "child" -> j.child).foreach { case (role, link) =>
      if (!linkSet.contains(link)) fail(j.label, s"unknown $role link '$link'")
    }
  }
  private val parentJoint: Map[String, UrdfJoint] = robot.joints.groupBy(_.child).map {
    case (child, Seq(j)) => child -> j
    case (child, js) => fail(s"link '$child'", s"has two parents (joints ${quoted(js.map(_.name))}): a loop")
  }
  private val childJoints: Map[String, Seq[UrdfJoint]] = robot.joints.groupBy(_.parent).withDefaultValue(Nil)
  private val root: String = linkNames.filterNot(parentJoint.contains) match {
    case Seq(r) => r
    case Seq()  => fail(robot.label, "no root link (every link is some joint's child): a loop")
    case roots  => fail(robot.label, s"several root links ${quoted(roots)}: the links must form one tree")
  }

  // Every link must hang off the root; only then do the walks below (pathTo, place) end. The walks loop
  // rather than recurse: a file may chain many thousands of links, deeper than the stack.
  private val connected: Set[String] = {
    val seen = mutable.HashSet(root)
    val todo = mutable.Stack(root)
    while (todo.nonEmpty) childJoints(todo.pop()).map(_.child).filter(seen.add).foreach(todo.push)
    seen.toSet
  }
  linkNames
    .find(!connected.contains(_))
    .foreach(l => fail(s"link '$l'", "is not connected to the root link: the joints form a loop"))

  private def duplicate(names: Seq[String]): Option[String] = names.diff(names.distinct).headOption

  /** The joints from the root to `link`, root first. */
  private def pathTo(link: String): List[UrdfJoint] =
    List.unfold(link)(l => parentJoint.get(l).map(j => (j, j.parent))).reverse

  /**
   * Every link reachable from the root, placed top-down; joints off the chain are locked at q = 0 (pose =
   * origin).
   */
  private def place(link: String, at: Placement, chainIndex: Map[String, Int]): Map[String, Placement] = {
    val placed = mutable.HashMap(link -> at)
    val todo = mutable.Stack(link)
    while (todo.nonEmpty) {
      val parent = todo.pop()
      childJoints(parent).foreach { j =>
        placed(j.child) = chainIndex.get(j.name) match {
          case Some(k) => Placement(Some(k), Transform.identity)
          case None    => Placement(placed(parent).carrier, placed(parent).pose.compose(j.origin))
        }
        todo.push(j.child)
      }
    }
    placed.toMap
  }

  def chain(tip: Option[String], allowMassless: Boolean): SerialChain = {
    val leaves = linkNames.filter(childJoints(_).isEmpty)
    val tipLink = tip match {
      case Some(t) if linkNames.contains(t) => t
      case Some(t) => fail(robot.label, s"unknown tip link '$t' (links: ${quoted(linkNames)})")
      case None if leaves.size == 1 => leaves.head
      case None => fail(robot.label, s"--tip is needed: leaves are ${few(leaves, identity)}")
    }
    val moving = pathTo(tipLink).flatMap(j => j.motion.map(kind => (j, kind))).toIndexedSeq
    if (moving.isEmpty)
      fail(robot.label, s"no moving joint between the root link '$root' and the tip link '$tipLink'")
    moving.find(_._1.mimic).foreach { case (j, _) =>
      fail(j.label, "mimic joints on the chain are not supported")
    }

    val placements =
      place(root, Placement(None, Transform.identity), moving.map(_._1.name).zipWithIndex.toMap)
    val bodies = robot.links
      .flatMap { link =>
        val at = placements(link.name)
        // Links fixed to the base never move: their mass loads no joint, and their numbers are not checked.
        for (k <- at.carrier; body <- link.inertial if !isEmpty(body)) yield {
          UrdfInertia.problem(body).foreach(problem => fail(s"link '${link.name}'", problem))
          k -> body.transformed(at.pose)
        }
      }
      .groupBy(_._1)

    val names = moving.map(_._1.name)
    // Links each chain joint carries, in file order; a link fixed to the base has no carrier.
    val carried: Map[Int, Seq[UrdfLink]] =
      robot.links.flatMap(l => placements(l.name).carrier.map(_ -> l)).groupMap(_._1)(_._2)
    def massive(l: UrdfLink) = l.inertial.exists(b => !isEmpty(b))
    // The first joint from which every carried link to the tip is massless: its torque and every later
    // joint's are identically zero (no mass, no inertia moves).
    val firstMassless =
      moving.indices.find(k => (k until moving.size).forall(m => !carried.getOrElse(m, Nil).exists(massive)))
    val masslessWarnings = firstMassless.toSeq.flatMap { k =>
      val joints = names.drop(k)
      val element = if (joints.size == 1) s"joint '${joints.head}'" else s"joints ${quoted(joints)}"
      val (bare, empty) =
        (k until moving.size).flatMap(carried.getOrElse(_, Nil)).partition(_.inertial.isEmpty)
      def links(ls: Seq[UrdfLink], problem: String) =
        if (ls.isEmpty) Nil
        else Seq(s"${if (ls.size == 1) "link" else "links"} ${quoted(ls.map(_.name))} $problem")
      val what =
        s"${if (joints.size == 1) "moves" else "move"} no mass (" +
          (links(bare, "without <inertial>") ++ links(empty, "with zero mass")).mkString(", ") + "): " +
          s"${if (joints.size == 1) "its torque is" else "their torques are"} identically zero"
      if (!allowMassless)
        fail(
          element,
          s"$what; give the links their <inertial>, or set ${Urdf.allowMasslessSetting} = true to accept it"
        )
      Seq(Warning(s"$source: $element", s"$what (accepted: ${Urdf.allowMasslessSetting} = true)"))
    }
    // A link a joint moves (not a frame fixed to another link) with no <inertial> is most likely a forgotten
    // one; joints already named above are not repeated link by link.
    val linkWarnings = robot.links.flatMap { l =>
      for {
        k <- placements(l.name).carrier.toSeq
        if l.inertial.isEmpty && !firstMassless.exists(k >= _)
        j <- parentJoint.get(l.name).toSeq if j.motion.isDefined
      } yield {
        val sources = carried(k).filter(massive).map(_.name)
        Warning(
          s"$source: link '${l.name}'",
          s"has no <inertial>, taken as massless: joint '${names(k)}' gets its own mass from " +
            (sources match {
              case Seq()  => "no link (only the links after it load it)"
              case Seq(x) => s"link '$x' only"
              case xs     => s"links ${quoted(xs)} only"
            })
        )
      }
    }

    SerialChain(
      robot.name,
      moving.zipWithIndex.map { case ((j, kind), k) =>
        ChainJoint(
          name = j.name,
          kind = kind,
          // The parent link's pose in the previous moving joint's frame takes in the fixed joints between
          // them.
          origin = placements(j.parent).pose.compose(j.origin),
          axis = j.axis,
          // Merged from the first real body on, so that a lone link keeps its numbers exactly.
          body = bodies.getOrElse(k, Nil).map(_._2).reduceOption(_ merge _).getOrElse(RigidBody.massless),
          velocityLimit = j.velocityLimit,
          effortLimit = j.effortLimit
        )
      },
      gravity = Vec3(0, 0, -9.81),
      warnings = masslessWarnings ++ linkWarnings,
      source = source,
      tipFrames = placements.collect {
        case (link, Placement(Some(k), pose)) if k == moving.size - 1 => link -> pose
      },
      tip = tipLink
    )
  }

  private def isEmpty(body: RigidBody): Boolean = body.mass == 0 && body.inertia.rows.flatten.forall(_ == 0)
}
