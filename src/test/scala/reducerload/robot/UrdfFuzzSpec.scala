package reducerload.robot

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.testutil.{Scratch, Seeds}

import java.nio.file.{Files, Path, Paths}

/**
 * The short form of [[UrdfFuzz]] (the long form is a documented command, docs/verification.md), and the
 * command line on the two URDFs of issue 30 whose mass was missing.
 */
class UrdfFuzzSpec extends AnyFlatSpec {
  behavior of "the URDF reader and the command line"

  private def resource(name: String): Path = Paths.get(getClass.getResource(s"/urdf/$name").toURI)

  it should "refuse a chain whose last joint moves no mass with one line, write nothing, and emit it when allowed" in {
    val file = resource("massless_last.urdf")
    val out = Scratch.dir("massless").resolve("out")
    val line = UrdfFuzz.refusedCleanly(file, "tool", out)
    assert(
      line.exists(l =>
        l.contains(s"$file: joint 'j2': moves no mass") && l.contains("'link2', 'tool'") &&
          l.contains("robot.allow-massless")
      ),
      line
    )
    val (status, lines) = UrdfFuzz.cli(
      "emit",
      "--robot",
      file.toString,
      "--max-acceleration",
      "10",
      "--robot.allow-massless",
      "true",
      "--target-dir",
      out.toString
    )
    assert(status == 0, lines.mkString("\n"))
    assert(lines.exists(l => l.startsWith(s"warning: $file: ") && l.contains("'j2'")), lines.mkString("\n"))
    assert(Files.list(out).toArray.map(_.toString).exists(_.endsWith(".sv")))
  }

  it should "print the warning of a moving link without <inertial> on the command line, once" in {
    val file = resource("massless_link.urdf")
    val (status, lines) = UrdfFuzz.cli("config", "--robot", file.toString, "--max-acceleration", "10")
    assert(status == 0, lines.mkString("\n"))
    assert(
      lines.filter(_.startsWith("warning:")) ==
        Seq(
          s"warning: $file: link 'link2': has no <inertial>, taken as massless: joint 'j2' gets its own mass from link 'tool' only"
        ),
      lines.mkString("\n")
    )
  }

  it should "name the URDF file when its velocity limits are missing or beyond the declared ranges' rule" in {
    val text = new String(Files.readAllBytes(resource("massless_link.urdf")), "UTF-8")
    Seq(
      "velocity=\"5000\"" -> "<limit velocity> taken for robot.max-velocity of joint 1",
      "" -> "joint 'j1' has no <limit velocity>: declare robot.max-velocity"
    ).foreach { case (limit, words) =>
      val dir = Scratch.dir("limits")
      val file =
        Files.write(dir.resolve("arm.urdf"), text.replaceFirst("velocity=\"2\"", limit).getBytes("UTF-8"))
      val line = UrdfFuzz.refusedCleanly(file, "tool", dir.resolve("out"))
      assert(line.exists(_.contains(s"$file: $words")), line)
    }
  }

  it should "run the seeded short form: valid chains checked, mutations refused cleanly, nothing crashes" in {
    val seed = Seeds("urdf-fuzz", 30L)
    val start = System.nanoTime()
    val summary = UrdfFuzz.runAll(seed, 0 until 100, Scratch.dir("urdf-fuzz"))
    println(summary.table(seed))
    println(f"[urdf-fuzz] short form: ${(System.nanoTime() - start) / 1e9}%.1f s")
    assert(summary.failures.isEmpty, summary.table(seed))
    assert(summary.passed > 25 && summary.refused > 25, summary.table(seed))
  }
}
