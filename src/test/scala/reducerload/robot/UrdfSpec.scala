package reducerload.robot

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.util.InputError

import java.nio.file.{Path, Paths}

class UrdfSpec extends AnyFlatSpec {
  behavior of "Urdf"

  private def resource(name: String): Path = Paths.get(getClass.getResource(s"/urdf/$name").toURI)
  private val tolerance = 1e-12

  private def close(a: Double, b: Double): Boolean = math.abs(a - b) <= tolerance
  private def assertVec(actual: Vec3, expected: Vec3, what: String): Unit =
    assert(
      actual.toSeq.zip(expected.toSeq).forall { case (a, b) => close(a, b) },
      s"$what: $actual, expected $expected"
    )
  private def assertMat(actual: Mat3, expected: Mat3, what: String): Unit =
    assert(
      actual.rows.flatten.zip(expected.rows.flatten).forall { case (a, b) => close(a, b) },
      s"$what: $actual, expected $expected"
    )
  private def rows(r0: Seq[Double], r1: Seq[Double], r2: Seq[Double]) = Mat3(
    IndexedSeq(r0, r1, r2).map(_.toIndexedSeq)
  )
  private def diag(x: Double, y: Double, z: Double) = Mat3.diagonal(Vec3(x, y, z))

  // Rotations by a quarter turn, written out (rpy 1.5707963267948966 snaps to exact 0/1 entries).
  private val rotZ90 = rows(Seq(0, -1, 0), Seq(1, 0, 0), Seq(0, 0, 1))
  private val rotX90 = rows(Seq(1, 0, 0), Seq(0, 0, -1), Seq(0, 1, 0))
  private val rotY90 = rows(Seq(0, 0, 1), Seq(0, 1, 0), Seq(-1, 0, 0))

  private val arm = resource("arm.urdf")

  it should "read a chain through a fixed joint, with rpy origins, negative " +
    "and unnormalised axes and limits" in {
      val chain = Urdf.read(arm, Some("l3"))
      assert(chain.name == "test_arm")
      assert(chain.gravity == Vec3(0, 0, -9.81))
      assert(chain.joints.map(_.name) == Seq("j1", "elbow", "wrist_slide"))
      assert(chain.joints.map(_.kind) == Seq(JointKind.Revolute, JointKind.Continuous, JointKind.Prismatic))
      val Seq(j1, elbow, slide) = chain.joints

      // j1: in the base frame, as written.
      assertMat(j1.origin.rotation, rotZ90, "j1 rotation")
      assertVec(j1.origin.translation, Vec3(0, 0, 0.5), "j1 translation")
      assertVec(j1.axis, Vec3(0, 0, -1), "j1 axis")
      assert(j1.velocityLimit.contains(2.0) && j1.effortLimit.contains(100.0))

      // elbow: the fixed joint 'mount' (Rx90 at (0.3, 0, 0)) composed with elbow's own (0, 0.2, 0):
      // translation (0.3, 0, 0) + Rx90 (0, 0.2, 0) = (0.3, 0, 0.2).
      assertMat(elbow.origin.rotation, rotX90, "elbow rotation")
      assertVec(elbow.origin.translation, Vec3(0.3, 0, 0.2), "elbow translation")
      assertVec(elbow.axis, Vec3(0, 0, 1), "elbow axis (0 0 2 normalised)")
      assert(elbow.velocityLimit.contains(3.0) && elbow.effortLimit.contains(20.0))

      assertMat(slide.origin.rotation, Mat3.identity, "wrist_slide rotation")
      assertVec(slide.origin.translation, Vec3(0.5, 0, 0), "wrist_slide translation")
      assertVec(slide.axis, Vec3(0, -1, 0), "wrist_slide axis")
      assert(slide.velocityLimit.contains(0.5) && slide.effortLimit.contains(50.0))
    }

  it should "merge a locked side branch into the link it hangs off and ignore the base's mass" in {
    val j1 = Urdf.read(arm, Some("l3")).joints.head
    // l1: 2 kg at (0.1, 0, 0), diag(0.01, 0.02, 0.03) turned by Rz90 -> diag(0.02, 0.01, 0.03).
    // carriage (locked slider, Rx90 at (0.1, 0.2, -0.1)): 2 kg at (0.1, 0.2, -0.1) + Rx90 (0, 0.1, 0)
    // = (0.1, 0.2, 0), diag(0.001, 0.002, 0.003) turned by Rx90 -> diag(0.001, 0.003, 0.002).
    // Together 4 kg at (0.1, 0.1, 0); each body is 0.1 m from it along y: parallel-axis terms
    // 2 * 0.01 on x and z per body -> diag(0.04, 0, 0.04). The base and camera (fixed to the base) add
    // nothing.
    assert(close(j1.body.mass, 4.0))
    assertVec(j1.body.com, Vec3(0.1, 0.1, 0), "j1 com")
    assertMat(j1.body.inertia, diag(0.061, 0.013, 0.072), "j1 inertia")
  }

  it should "turn an inertial frame into the link frame and merge the tool fixed after the tip" in {
    val Seq(_, elbow, slide) = Urdf.read(arm, Some("l3")).joints
    // l2: rod inertia diag(0.02, 0.02, 0.001) pitched by 90 degrees -> diag(0.001, 0.02, 0.02); bracket is
    // massless.
    assert(close(elbow.body.mass, 1.5))
    assertVec(elbow.body.com, Vec3(0.25, 0, 0), "elbow com")
    assertMat(
      elbow.body.inertia,
      rotY90 * diag(0.02, 0.02, 0.001) * rotY90.transpose,
      "elbow inertia (rotation)"
    )
    assertMat(elbow.body.inertia, diag(0.001, 0.02, 0.02), "elbow inertia")
    // l3 0.5 kg at z 0.05 and tool 0.5 kg at z 0.1 (a child of the tip): 1 kg at z 0.075, each 0.025
    // from it: diag(0.001) + 2 * 0.5 * 0.025^2 on x and y.
    assert(close(slide.body.mass, 1.0))
    assertVec(slide.body.com, Vec3(0, 0, 0.075), "wrist_slide com")
    assertMat(slide.body.inertia, diag(0.001625, 0.001625, 0.001), "wrist_slide inertia")
  }

  it should "treat a tip reached through fixed joints like the last moving link" in {
    // The same chain; only the link it is said to end at differs.
    assert(Urdf.read(arm, Some("tcp")).copy(tip = "l3") == Urdf.read(arm, Some("l3")))
  }

  it should "lock the joints after a tip and merge what they carry" in {
    val chain = Urdf.read(arm, Some("l2"))
    assert(chain.joints.map(_.name) == Seq("j1", "elbow"))
    // l2 1.5 kg at (0.25, 0, 0) + l3 0.5 kg at (0.5, 0, 0.05) + tool 0.5 kg at (0.5, 0, 0.1), from
    // c = (0.35, 0, 0.03): d = (-0.1, 0, -0.03), (0.15, 0, 0.02), (0.15, 0, 0.07).
    // Ixx = 0.001 + 0.001 + 1.5*0.0009 + 0.5*0.0004 + 0.5*0.0049 = 0.006
    // Iyy = 0.02 + 0.001 + 1.5*0.0109 + 0.5*0.0229 + 0.5*0.0274 = 0.0625
    // Izz = 0.02 + 0.001 + 1.5*0.01 + 0.5*0.0225 + 0.5*0.0225 = 0.0585
    // Ixz = -(1.5*0.003 + 0.5*0.003 + 0.5*0.0105) = -0.01125   (Pinocchio's buildReducedModel gives the same)
    val body = chain.joints(1).body
    assert(close(body.mass, 2.5))
    assertVec(body.com, Vec3(0.35, 0, 0.03), "elbow com")
    assertMat(
      body.inertia,
      rows(Seq(0.006, 0, -0.01125), Seq(0, 0.0625, 0), Seq(-0.01125, 0, 0.0585)),
      "elbow inertia"
    )
  }

  it should "read the UR5 (published kinematics) like Pinocchio, with tip tool0" in {
    val ur5 = resource("ur5_kinematics.urdf")
    val e = intercept[InputError](Urdf.read(ur5, None))
    assert(
      e.getMessage.endsWith("robot 'ur5': --tip is needed: leaves are ee_link, base, tool0"),
      e.getMessage
    )
    val chain = Urdf.read(ur5, Some("tool0"))
    assert(
      chain.joints.map(_.name) == Seq(
        "shoulder_pan_joint",
        "shoulder_lift_joint",
        "elbow_joint",
        "wrist_1_joint",
        "wrist_2_joint",
        "wrist_3_joint"
      )
    )
    val translations = Seq(
      Vec3(0, 0, 0.089159),
      Vec3(0, 0.13585, 0),
      Vec3(0, -0.1197, 0.425),
      Vec3(0, 0, 0.39225),
      Vec3(0, 0.093, 0),
      Vec3(0, 0, 0.09465)
    )
    val rotations = Seq(Mat3.identity, rotY90, Mat3.identity, rotY90, Mat3.identity, Mat3.identity)
    val axes = Seq(Vec3(0, 0, 1), Vec3(0, 1, 0), Vec3(0, 1, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0, 1, 0))
    val masses = Seq(3.7, 8.393, 2.275, 1.219, 1.219, 0.1879)
    val coms = Seq(Vec3.zero, Vec3(0, 0, 0.28), Vec3(0, 0, 0.25), Vec3.zero, Vec3.zero, Vec3.zero)
    val inertias = Seq(
      diag(0.010267495893, 0.010267495893, 0.00666),
      diag(0.22689067591, 0.22689067591, 0.0151074),
      diag(0.049443313556, 0.049443313556, 0.004095),
      diag(0.111172755531, 0.111172755531, 0.21942),
      diag(0.111172755531, 0.111172755531, 0.21942),
      diag(0.0171364731454, 0.0171364731454, 0.033822)
    )
    chain.joints.zipWithIndex.foreach { case (j, k) =>
      assertVec(j.origin.translation, translations(k), s"${j.name} translation")
      assertMat(j.origin.rotation, rotations(k), s"${j.name} rotation")
      assertVec(j.axis, axes(k), s"${j.name} axis")
      assert(close(j.body.mass, masses(k)), s"${j.name} mass")
      assertVec(j.body.com, coms(k), s"${j.name} com")
      assertMat(j.body.inertia, inertias(k), s"${j.name} inertia")
    }
    assert(chain.joints.map(_.effortLimit.get) == Seq(150.0, 150.0, 150.0, 28.0, 28.0, 28.0))
  }

  // A minimal valid robot the refusal cases start from.
  private val unitInertia = """<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>"""
  private def massive(name: String) =
    s"""<link name="$name"><inertial><mass value="1"/>$unitInertia</inertial></link>"""
  private def joint(
      name: String,
      parent: String,
      child: String,
      kind: String = "revolute",
      extra: String = ""
  ) =
    s"""<joint name="$name" type="$kind"><parent link="$parent"/><child link="$child"/>$extra</joint>"""
  private def robot(body: String*) = s"""<?xml version="1.0"?><robot name="r">${body.mkString}</robot>"""
  private val minimal = robot("""<link name="a"/>""", massive("b"), joint("j", "a", "b"))

  it should "accept the minimal robot and a missing axis (x); a body moving no mass only when allowed" in {
    val j = Urdf.parse("ok.urdf", minimal, None).joints.head
    assert(j.axis == Vec3(1, 0, 0) && j.origin == Transform.identity && j.body.mass == 1.0)
    assert(j.velocityLimit.isEmpty && j.effortLimit.isEmpty)
    val bare = robot("""<link name="a"/><link name="b"/>""", joint("j", "a", "b"))
    val e = intercept[InputError](Urdf.parse("ok.urdf", bare, None))
    assert(
      e.getMessage == "ok.urdf: joint 'j': moves no mass (link 'b' without <inertial>): its torque is " +
        "identically zero; give the links their <inertial>, or set robot.allow-massless = true to accept it"
    )
    val massless = Urdf.parse("ok.urdf", bare, None, allowMassless = true)
    assert(massless.joints.head.body == RigidBody.massless)
    assert(massless.warnings.map(_.where) == Seq("ok.urdf: joint 'j'"))
    assert(Urdf.parse("ok.urdf", minimal, None).warnings.isEmpty)
  }

  it should "refuse a URDF whose last moving link and tool have no <inertial> (issue 30, item 1) unless allowed" in {
    val file = resource("massless_last.urdf")
    val e = intercept[InputError](Urdf.read(file, None))
    assert(
      e.getMessage == s"$file: joint 'j2': moves no mass (links 'link2', 'tool' without <inertial>): its " +
        "torque is identically zero; give the links their <inertial>, or set robot.allow-massless = true to accept it"
    )
    val chain = Urdf.read(file, None, allowMassless = true)
    assert(chain.joints(1).body == RigidBody.massless && chain.joints(0).body.mass == 2.0)
    assert(
      chain.warnings.map(_.toString) == Seq(
        s"warning: $file: joint 'j2': moves no mass (links 'link2', 'tool' without <inertial>): its torque is " +
          "identically zero (accepted: robot.allow-massless = true)"
      )
    )
    // Several joints at the end: named together, from the first.
    val two = robot(
      """<link name="a"/>""",
      massive("b"),
      """<link name="c"/><link name="d"/>""",
      joint("j", "a", "b"),
      joint("k", "b", "c"),
      joint("l", "c", "d")
    )
    val both = intercept[InputError](Urdf.parse("two.urdf", two, None))
    assert(both.getMessage.startsWith("two.urdf: joints 'k', 'l': move no mass (links 'c', 'd' without"))
    // A link with an explicit zero mass counts as none.
    val zero = robot(
      """<link name="a"/>""",
      """<link name="b"><inertial><mass value="0"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial></link>""",
      joint("j", "a", "b")
    )
    assert(
      intercept[InputError](Urdf.parse("zero.urdf", zero, None)).getMessage
        .contains("moves no mass (link 'b' with zero mass)")
    )
  }

  it should "warn about a moving link without <inertial> whose tool has one (issue 30, item 2), not about frames" in {
    val file = resource("massless_link.urdf")
    val chain = Urdf.read(file, None)
    assert(chain.joints(1).body.mass == 0.5)
    assert(
      chain.warnings.map(_.toString) == Seq(
        s"warning: $file: link 'link2': has no <inertial>, taken as massless: joint 'j2' gets its own mass " +
          "from link 'tool' only"
      )
    )
    // A link fixed to another (bracket, tcp) is a frame: quiet; so are the golden robots.
    assert(Urdf.read(arm, Some("l3")).warnings.isEmpty)
    assert(Urdf.read(Paths.get("golden/robots/ur5_robot.urdf"), Some("tool0")).warnings.isEmpty)
    assert(Urdf.read(Paths.get("golden/robots/panda.urdf"), Some("panda_hand")).warnings.isEmpty)
    // A massless middle link: its joint is loaded by the links after it.
    val middle = robot(
      """<link name="a"/><link name="b"/>""",
      massive("c"),
      joint("j", "a", "b"),
      joint("k", "b", "c")
    )
    assert(
      Urdf.parse("m.urdf", middle, None).warnings.map(_.toString) == Seq(
        "warning: m.urdf: link 'b': has no <inertial>, taken as massless: joint 'j' gets its own mass from no " +
          "link (only the links after it load it)"
      )
    )
  }

  it should "refuse numbers beyond an arm's and read a chain of many thousand links without a stack overflow" in {
    def refused(xml: String, words: String*): Unit = {
      val message = intercept[InputError](Urdf.parse("big.urdf", xml, None)).getMessage
      words.foreach(w => assert(message.contains(w), message))
    }
    refused(
      minimal.replace("""<mass value="1"/>""", """<mass value="1e308"/>"""),
      "link 'b'",
      "<mass value> 1.0E308 kg"
    )
    refused(minimal.replace("""ixx="1"""", """ixx="1e9""""), "link 'b'", "<inertia ixx>")
    refused(
      minimal.replace("<parent ", """<origin xyz="0 1e3 0"/><parent """),
      "joint 'j'",
      "<origin xyz> 1000.0 m is beyond 100.0 m"
    )
    refused(
      minimal
        .replace("1\"/><inertia", "1\"/><inertia")
        .replace("""<mass value="1"/>""", s"""<mass value="${"9" * 400}"/>"""),
      "is not a finite number"
    )
    // An axis whose norm overflows or underflows a double is still a direction.
    val huge = Urdf.parse(
      "ok.urdf",
      minimal.replace("<parent ", """<axis xyz="0 0 1.7976931348623157e308"/><parent """),
      None
    )
    assert(huge.joints.head.axis == Vec3(0, 0, 1))
    val tiny =
      Urdf.parse("ok.urdf", minimal.replace("<parent ", """<axis xyz="0 -1e-320 0"/><parent """), None)
    assert(tiny.joints.head.axis == Vec3(0, -1, 0))
    val n = 100000
    val tail = (0 until n).map(k =>
      s"""<link name="x${k + 1}"/>""" + joint(s"x$k", if (k == 0) "b" else s"x$k", s"x${k + 1}", "fixed")
    )
    val long = robot(("""<link name="a"/>""" +: massive("b") +: joint("j", "a", "b") +: tail): _*)
    assert(Urdf.parse("long.urdf", long, None).joints.head.body.mass == 1.0)
    val many = robot(
      ("""<link name="a"/>""" +: massive("b") +: joint("j", "a", "b") +: (0 until 20).map(k =>
        s"""<link name="y$k"/>""" + joint(s"y$k", "a", s"y$k", "fixed")
      )): _*
    )
    val e = intercept[InputError](Urdf.parse("many.urdf", many, None))
    assert(
      e.getMessage.endsWith("--tip is needed: leaves are b, y0, y1, y2, y3, y4, y5, y6 and 13 more"),
      e.getMessage
    )
  }

  it should "check the inertia of every link the chain carries, and only those" in {
    val rod =
      """<link name="c"><inertial><mass value="1"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="1"/></inertial></link>"""
    // Fixed to the base: never loads a joint, so a sloppy camera or base tensor does not stop the reader.
    assert(
      Urdf
        .parse(
          "ok.urdf",
          robot(
            """<link name="a"/>""",
            massive("b"),
            rod,
            joint("j", "a", "b"),
            joint("k", "a", "c", kind = "fixed")
          ),
          Some("b")
        )
        .size == 1
    )
    // Carried by j through a locked side branch: refused.
    val e = intercept[InputError](
      Urdf.parse(
        "bad.urdf",
        robot(
          """<link name="a"/>""",
          massive("b"),
          rod,
          joint("j", "a", "b"),
          joint("k", "b", "c", kind = "prismatic")
        ),
        Some("b")
      )
    )
    assert(
      e.getMessage.startsWith("bad.urdf: link 'c': principal moments") && e.getMessage.contains(
        "triangle inequality"
      ),
      e.getMessage
    )
    // Zero up to rounding (as in iCub's URDF) is a point mass.
    val point =
      """<link name="b"><inertial><mass value="1"/><inertia ixx="0" ixy="0" ixz="2.4e-35" iyy="0" iyz="0" izz="0"/></inertial></link>"""
    assert(
      Urdf
        .parse("ok.urdf", robot("""<link name="a"/>""", point, joint("j", "a", "b")), None)
        .joints
        .head
        .body
        .mass == 1.0
    )
  }

  it should "refuse malformed or unsupported URDFs with one line naming the file and the element" in {
    def refused(xml: String, words: String*): Unit = {
      val e = intercept[InputError](Urdf.parse("bad.urdf", xml, None))
      val message = e.getMessage
      assert(!message.contains("\n"), s"error spans lines: $message")
      ("bad.urdf: " +: words).foreach(w => assert(message.contains(w), s"'$message' does not mention '$w'"))
    }
    def replaced(from: String, to: String) = { assert(minimal.contains(from)); minimal.replace(from, to) }

    refused("this is not XML", "XML", "line 1")
    refused("""<robot name="r"><link name="a"></robot>""", "XML")
    refused("""<model name="r"/>""", "<model>", "<robot>")
    refused("""<robot><link name="a"/></robot>""", "<robot>", "name")
    // No DTDs, so no external entities (file or network reads) either.
    refused(
      """<?xml version="1.0"?><!DOCTYPE robot [<!ENTITY x SYSTEM "file:///etc/passwd">]><robot name="&x;"/>""",
      "XML",
      "DOCTYPE"
    )
    refused(replaced("""<link name="a"/>""", "<link/>"), "link #1", "name")
    refused(replaced("""type="revolute"""", ""), "joint 'j'", "type")
    refused(replaced("""<parent link="a"/>""", ""), "joint 'j'", "<parent")
    refused(replaced("""<child link="b"/>""", """<child/>"""), "joint 'j'", "<child")
    refused(replaced("<parent ", """<origin xyz="0 0 x"/><parent """), "joint 'j'", "origin xyz", "0 0 x")
    refused(
      replaced("<parent ", """<origin rpy="0 0"/><parent """),
      "joint 'j'",
      "origin rpy",
      "3 finite numbers"
    )
    refused(replaced("<parent ", """<origin xyz="0 0 1e999"/><parent """), "joint 'j'", "origin xyz")
    refused(replaced("<parent ", """<origin/><origin/><parent """), "joint 'j'", "more than one <origin>")
    refused(replaced("""<mass value="1"/>""", """<mass value="NaN"/>"""), "link 'b'", "<mass value>", "NaN")
    refused(replaced("""<mass value="1"/>""", """<mass/>"""), "link 'b'", "value")
    refused(replaced("""<mass value="1"/>""", ""), "link 'b'", "no <mass>")
    refused(replaced(unitInertia, ""), "link 'b'", "no <inertia>")
    refused(replaced("""ixx="1"""", """ixx="inf""""), "link 'b'", "<inertia ixx>")
    refused(replaced("""iyz="0"""", ""), "link 'b'", "iyz")
    refused(replaced("""<mass value="1"/>""", """<mass value="-1"/>"""), "link 'b'", "negative mass")
    refused(replaced("""ixx="1"""", """ixx="-1""""), "link 'b'", "not positive semi-definite")
    refused(replaced("""izz="1"""", """izz="3""""), "link 'b'", "triangle inequality")
    refused(replaced("""ixy="0"""", """ixy="2""""), "link 'b'", "not positive semi-definite")
    refused(replaced("""type="revolute"""", """type="floating""""), "joint 'j'", "floating")
    refused(replaced("""type="revolute"""", """type="planar""""), "joint 'j'", "planar")
    refused(
      replaced("""type="revolute"""", """type="spherical""""),
      "joint 'j'",
      "unknown joint type 'spherical'"
    )
    refused(replaced("<parent ", """<axis xyz="0 0 0"/><parent """), "joint 'j'", "zero <axis")
    refused(
      replaced("<parent ", """<limit velocity="-1"/><parent """),
      "joint 'j'",
      "negative <limit velocity>"
    )
    refused(replaced("<parent ", """<limit effort="a lot"/><parent """), "joint 'j'", "<limit effort>")
    refused(replaced("<parent ", """<mimic joint="k"/><parent """), "joint 'j'", "mimic")
    refused(replaced("""<child link="b"/>""", """<child link="c"/>"""), "joint 'j'", "unknown child link 'c'")
    refused(
      replaced("""<parent link="a"/>""", """<parent link="z"/>"""),
      "joint 'j'",
      "unknown parent link 'z'"
    )
    refused(
      replaced("""<child link="b"/>""", """<child link="c&#10;d"/>"""),
      "joint 'j'",
      "unknown child link 'c d'"
    )
    refused(
      robot("""<link name="a"/>""", massive("b"), massive("b"), joint("j", "a", "b")),
      "link 'b'",
      "defined twice"
    )
    refused(
      robot("""<link name="a"/>""", massive("b"), massive("c"), joint("j", "a", "b"), joint("j", "a", "c")),
      "joint 'j'",
      "defined twice"
    )
    refused(
      robot("""<link name="a"/><link name="c"/>""", massive("b"), joint("j", "a", "b"), joint("k", "c", "b")),
      "link 'b'",
      "two parents",
      "'j', 'k'",
      "loop"
    )
    refused(
      robot("""<link name="a"/>""", massive("b"), joint("j", "a", "b"), joint("k", "b", "a")),
      "robot 'r'",
      "no root link"
    )
    refused(
      robot("""<link name="a"/>""", massive("b"), massive("c"), joint("j", "a", "b"), joint("k", "c", "c")),
      "link 'c'",
      "loop"
    )
    refused(
      robot("""<link name="a"/><link name="x"/>""", massive("b"), joint("j", "a", "b")),
      "robot 'r'",
      "several root links 'a', 'x'"
    )
    refused(
      robot("""<link name="a"/>""", massive("b"), massive("c"), joint("j", "a", "b"), joint("k", "a", "c")),
      "robot 'r'",
      "--tip is needed: leaves are b, c"
    )
    refused(
      robot("""<link name="a"/>""", massive("b"), joint("j", "a", "b", kind = "fixed")),
      "robot 'r'",
      "no moving joint",
      "'a'",
      "'b'"
    )
    val e = intercept[InputError](Urdf.parse("bad.urdf", minimal, Some("hand")))
    assert(e.getMessage == "bad.urdf: robot 'r': unknown tip link 'hand' (links: 'a', 'b')")
    val missing = intercept[InputError](Urdf.read(Paths.get("no/such/robot.urdf"), None))
    assert(
      missing.getMessage ==
        s"no/such/robot.urdf: no such file (looked for ${Paths.get("no/such/robot.urdf").toAbsolutePath})"
    )
    val directory = intercept[InputError](Urdf.read(Paths.get("golden/robots"), None))
    assert(directory.getMessage.startsWith("golden/robots: is a directory, not a file"))
  }
}
