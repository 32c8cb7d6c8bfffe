package reducerload.robot

import scala.collection.mutable.ArrayBuffer
import scala.util.Random

/**
 * A generated URDF and what reading it must give, worked out by the generator on its own: the moving joints'
 * origins composed through the fixed joints, and every link's body in the frame of the joint that moves it,
 * kept apart (the reader merges them; [[reducerload.dynamics.LagrangeReference]] sums them one by one).
 *
 * @param expected
 *   the chain's joints (names, kinds, origins, axes; the bodies are not used)
 * @param bodies
 *   per moving joint, the bodies of the links it moves
 * @param bareLinks
 *   links a joint moves that have no `<inertial>`: each must be warned about
 */
final case class GeneratedUrdf(
    xml: String,
    tip: String,
    expected: SerialChain,
    bodies: IndexedSeq[Seq[RigidBody]],
    bareLinks: Seq[String]
) {
  def prismatic: Option[String] = expected.joints.find(_.kind == JointKind.Prismatic).map(_.name)
}

/**
 * Seeded random serial chains written as URDF: 2 to 8 moving joints (revolute and continuous, now and then a
 * prismatic one), any axes (axis-aligned, negative, non-normalised, oblique), rpy origins (quarter turns and
 * arbitrary), fixed joints and links in between, locked side branches, a tool and a massless tool0; masses
 * from 1e-6 to 1e4 kg and inertias of boxes from cubes to needles and plates (near-singular).
 */
object RandomUrdf {
  private def num(x: Double): String = x.toString
  private def vec(v: Vec3): String = v.toSeq.map(num).mkString(" ")

  private def angle(rng: Random): Double = rng.nextInt(4) match {
    case 0 => 0.0
    case 1 => (rng.nextInt(5) - 2) * 1.5707963267948966 // quarter turns as URDFs write them
    case _ => (rng.nextDouble() * 2 - 1) * math.Pi
  }

  /** An origin: its XML and the transform it stands for. */
  private def origin(rng: Random, scale: Double): (String, Transform) = {
    val rpy = Vec3(angle(rng), angle(rng), angle(rng))
    val xyz = Vec3(rng.nextDouble() - 0.5, rng.nextDouble() - 0.5, rng.nextDouble() - 0.5) * scale
    (
      s"""<origin xyz="${vec(xyz)}" rpy="${vec(rpy)}"/>""",
      Transform(Mat3.rpy(rpy.x, rpy.y, rpy.z), xyz)
    )
  }

  private def mass(rng: Random): Double = rng.nextInt(10) match {
    case 0 => 1e-6 * (1 + rng.nextDouble())
    case 1 => 1e4 * (0.5 + rng.nextDouble() / 2)
    case _ => math.pow(10, rng.nextDouble() * 4 - 2)
  }

  /** A box's inertia about its centre, turned: sides from equal to 1e-4 of each other (needles, plates). */
  private def inertia(rng: Random, m: Double): Mat3 = {
    def side() = if (rng.nextInt(5) == 0) 1e-4 * rng.nextDouble() else 0.05 + 0.5 * rng.nextDouble()
    val (a, b, c) = (side(), side(), side())
    val principal = Mat3.diagonal(Vec3(b * b + c * c, a * a + c * c, a * a + b * b) * (m / 12))
    val r = Mat3.rpy(angle(rng), angle(rng), angle(rng))
    r * principal * r.transpose
  }

  /** An `<inertial>` element and the body it describes in its link's frame. */
  private def inertial(rng: Random): (String, RigidBody) = {
    val m = mass(rng)
    val i = inertia(rng, m)
    val (o, t) = origin(rng, 0.4)
    val xml = s"""<inertial>$o<mass value="${num(m)}"/><inertia ixx="${num(i(0, 0))}" ixy="${num(
        i(0, 1)
      )}" ixz="${num(i(0, 2))}" iyy="${num(i(1, 1))}" iyz="${num(i(1, 2))}" izz="${num(
        i(2, 2)
      )}"/></inertial>"""
    (xml, RigidBody(m, Vec3.zero, i).transformed(t))
  }

  /** The axis as written (any length, sometimes axis-aligned or negative) and as a unit vector. */
  private def axis(rng: Random): (Vec3, Vec3) = {
    val written =
      if (rng.nextBoolean())
        Seq(Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(-1, 0, 0))(rng.nextInt(5)) *
          (if (rng.nextInt(4) == 0) 0.5 + 3 * rng.nextDouble() else 1.0)
      else {
        val v = Vec3(rng.nextGaussian(), rng.nextGaussian(), rng.nextGaussian())
        if (v.norm < 1e-3) Vec3(0, 1, 0) else v
      }
    (written, written * (1 / written.norm))
  }

  def robot(rng: Random, prismaticChance: Double = 0.1): GeneratedUrdf = {
    val n = 2 + rng.nextInt(7)
    val xml = ArrayBuffer.empty[String]
    val joints = ArrayBuffer.empty[ChainJoint]
    val bodies = IndexedSeq.fill(n)(ArrayBuffer.empty[RigidBody])
    val bare = ArrayBuffer.empty[String]
    def link(name: String, body: Option[String]) =
      xml += s"""<link name="$name">${body.getOrElse("")}</link>"""
    def joint(name: String, kind: String, parent: String, child: String, extra: String) =
      xml += s"""<joint name="$name" type="$kind"><parent link="$parent"/><child link="$child"/>$extra</joint>"""
    // The base may have mass of its own: fixed to the world, it loads no joint.
    link("base", if (rng.nextBoolean()) Some(inertial(rng)._1) else None)
    var current = "base"
    var pose = Transform.identity // `current` in the frame of the last moving joint (the base before joint 1)
    val prismaticAt = if (rng.nextDouble() < prismaticChance) Some(rng.nextInt(n)) else None
    (0 until n).foreach { k =>
      (0 until rng.nextInt(3)).foreach { f =>
        val name = s"mount${k}_$f"
        val (o, t) = origin(rng, 0.4)
        val massive = rng.nextBoolean()
        val body = if (massive) Some(inertial(rng)) else None
        link(name, body.map(_._1))
        joint(s"fix${k}_$f", "fixed", current, name, o)
        pose = pose.compose(t)
        if (k > 0) body.foreach(b => bodies(k - 1) += b._2.transformed(pose))
        current = name
      }
      val kind =
        if (prismaticAt.contains(k)) JointKind.Prismatic
        else if (rng.nextInt(4) == 0) JointKind.Continuous
        else JointKind.Revolute
      val (o, t) = origin(rng, 0.6)
      val (written, unit) = axis(rng)
      val name = s"joint$k"
      val limit = s"""<limit velocity="${num(0.5 + 3 * rng.nextDouble())}" effort="100"/>"""
      joint(name, kind.name, current, s"link$k", s"""$o<axis xyz="${vec(written)}"/>$limit""")
      joints += ChainJoint(name, kind, pose.compose(t), unit, RigidBody.massless)
      // The last link always has mass, so that no joint moves nothing (that is refused, see UrdfSpec).
      val body = if (k < n - 1 && rng.nextInt(6) == 0) None else Some(inertial(rng))
      link(s"link$k", body.map(_._1))
      body.fold[Unit](bare += s"link$k")(b => bodies(k) += b._2)
      current = s"link$k"
      pose = Transform.identity
      if (rng.nextInt(5) == 0) { // a locked side branch: a finger, a cable carrier
        val (so, st) = origin(rng, 0.3)
        val (sb, body) = inertial(rng)
        val sideKind = Seq("fixed", "revolute", "prismatic")(rng.nextInt(3))
        link(s"side$k", Some(sb))
        joint(s"side_joint$k", sideKind, current, s"side$k", s"""$so<axis xyz="0 0 1"/>$limit""")
        bodies(k) += body.transformed(st)
      }
    }
    val (to, tt) = origin(rng, 0.2)
    val tool = if (rng.nextBoolean()) Some(inertial(rng)) else None
    link("tool", tool.map(_._1))
    joint("tool_joint", "fixed", current, "tool", to)
    tool.foreach(b => bodies(n - 1) += b._2.transformed(tt))
    link("tool0", None)
    joint("tool0_joint", "fixed", "tool", "tool0", origin(rng, 0.1)._1)
    val shuffled = rng.shuffle(xml.toSeq) // a URDF lists links and joints in any order
    GeneratedUrdf(
      s"""<?xml version="1.0"?>\n<robot name="random$n">\n${shuffled.mkString("\n")}\n</robot>\n""",
      "tool0",
      SerialChain(s"random$n", joints.toIndexedSeq, Vec3(0, 0, -9.81)),
      bodies.map(_.toSeq),
      bare.toSeq
    )
  }
}
