package reducerload.robot

import reducerload.app.Main
import reducerload.arm.{ArmModel, ArmSample}
import reducerload.compiler.Compiler
import reducerload.config.LoadParams
import reducerload.dynamics.{LagrangeReference, RandomChains, Rnea}
import reducerload.graph.{ScheduleRequest, Storage}
import reducerload.sim.rtl.VerilatorHarness
import reducerload.util.InputError

import java.io.{ByteArrayOutputStream, OutputStream, PrintStream}
import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path, Paths}
import scala.util.Random

/** What one fuzz case came to. */
sealed trait FuzzOutcome { def detail: String }
object FuzzOutcome {

  /** A valid robot read, compiled and checked (model within its bound, RNEA equal to Euler-Lagrange). */
  final case class Passed(detail: String) extends FuzzOutcome

  /** Refused through the command line: one line naming the file, exit 2, nothing written. */
  final case class Refused(detail: String) extends FuzzOutcome

  /** Anything else: a crash, a stack trace, a wrong number, a valid robot refused, files written. */
  final case class Failed(detail: String) extends FuzzOutcome
}

/**
 * URDF fuzzing: even cases are random valid chains ([[RandomUrdf]]), odd ones mutations ([[UrdfMutations]])
 * of the golden UR5 and Panda. Each case has its own generator, seeded from the run's seed and its number, so
 * any case reruns alone:
 * {{{
 * ./sbt "Test/runMain reducerload.robot.UrdfFuzz --cases 5000 --seed 1"
 * ./sbt "Test/runMain reducerload.robot.UrdfFuzz --seed 1 --case 123"
 * }}}
 */
object UrdfFuzz {
  import FuzzOutcome._

  private lazy val golden: IndexedSeq[(String, String)] = IndexedSeq(
    "golden/robots/ur5_robot.urdf" -> "tool0",
    "golden/robots/panda.urdf" -> "panda_hand"
  ).map { case (f, tip) => (new String(Files.readAllBytes(Paths.get(f)), StandardCharsets.UTF_8), tip) }

  /** Angles and rates a generated chain is checked at, within its declared ranges. */
  private val samplesPerChain = 3
  private val maxAcceleration = 8.0

  /** The refusal of a robot whose torques need more bits than the formats allow (a capacity, not a bug). */
  private val Capacity = "narrow the declared ranges"

  private def caseRandom(seed: Long, index: Int): Random = new Random(seed * 1000003L + index)

  /** The command line in-process: exit status and the lines it printed on standard error. */
  def cli(args: String*): (Int, Seq[String]) = {
    val err = new ByteArrayOutputStream()
    val silent = new PrintStream(OutputStream.nullOutputStream())
    val status = Console.withOut(silent)(Main.execute(args, new PrintStream(err, true, "UTF-8")))
    (status, new String(err.toByteArray, StandardCharsets.UTF_8).linesIterator.toSeq)
  }

  /**
   * The fuzz checks reading and numerics, not the device fit: one explicit schedule (one clock per sample,
   * registers) keeps each case to one scheduling instead of the fit's search over clocks per sample.
   */
  private val oneClock = ScheduleRequest(clocksPerSample = Some(1), storage = Some(Storage.Registers))
  private val oneClockFlags = Seq("--clocks-per-sample", "1", "--schedule.storage", "registers")

  /** A refusal as the issue asks: exit 2, one line `error: <file>: ...`, nothing in the output directory. */
  def refusedCleanly(file: Path, tip: String, out: Path): Either[String, String] = {
    val (status, lines) =
      cli(
        Seq(
          "emit",
          "--robot",
          file.toString,
          "--tip",
          tip,
          "--max-acceleration",
          "10",
          "--target-dir",
          out.toString
        )
          ++ oneClockFlags: _*
      )
    if (status != 2) Left(s"exit status $status, not 2 (${lines.take(3).mkString(" | ")})")
    else if (lines.size != 1)
      Left(s"${lines.size} lines on standard error: ${lines.take(3).mkString(" | ").take(300)}")
    else if (!lines.head.startsWith("error: ") || !lines.head.contains(file.toString))
      Left(s"the line does not name the file: ${lines.head.take(300)}")
    else if (lines.head.length < s"error: $file: ".length + 8) Left(s"no problem named: ${lines.head}")
    else if (Files.exists(out)) Left(s"$out was created")
    else Right(lines.head)
  }

  def run(seed: Long, index: Int, dir: Path): FuzzOutcome = {
    val rng = caseRandom(seed, index)
    val caseDir = Files.createDirectories(dir.resolve(s"case$index"))
    try
      if (index % 2 == 0) generated(rng, caseDir)
      else mutated(rng, caseDir, golden((index / 2) % golden.size))
    catch {
      case e: Throwable =>
        val where = e.getStackTrace.take(4).mkString(" < ")
        Failed(s"${e.getClass.getName}: ${String.valueOf(e.getMessage).take(300)} at $where")
    } finally VerilatorHarness.deleteTree(caseDir)
  }

  private def mutated(rng: Random, dir: Path, original: (String, String)): FuzzOutcome = {
    val m = UrdfMutations.mutate(rng, original._1, original._2)
    val file = dir.resolve("mutated.urdf")
    Files.write(file, m.bytes)
    val steps = m.steps.mkString("; ")
    val (status, lines) =
      cli(
        Seq(
          "config",
          "--robot",
          file.toString,
          "--tip",
          m.tip,
          "--max-acceleration",
          "10"
        ) ++ oneClockFlags: _*
      )
    status match {
      case 0 => Passed(s"still valid after: $steps")
      case 2 =>
        refusedCleanly(file, m.tip, dir.resolve("out")) match {
          case Right(line) => Refused(s"$steps -> ${line.take(200)}")
          case Left(why)   => Failed(s"$steps -> $why")
        }
      case s => Failed(s"$steps -> exit status $s: ${lines.mkString(" | ").take(300)}")
    }
  }

  private def close(a: Double, b: Double, scale: Double): Boolean = math.abs(a - b) <= 1e-9 * (1 + scale)

  private def generated(rng: Random, dir: Path): FuzzOutcome = {
    val g = RandomUrdf.robot(rng)
    val file = dir.resolve("generated.urdf")
    Files.write(file, g.xml.getBytes(StandardCharsets.UTF_8))
    val label = s"${g.expected.size} joints"
    val chain =
      try Urdf.read(file, Some(g.tip))
      catch { case e: InputError => return Failed(s"$label: a valid robot refused: ${e.getMessage}") }
    // The reader's chain against the generator's own composition.
    val shape = chain.joints.zip(g.expected.joints).forall { case (a, b) =>
      a.name == b.name && a.kind == b.kind &&
      a.axis.toSeq.zip(b.axis.toSeq).forall { case (x, y) => close(x, y, 1) } &&
      a.origin.translation.toSeq.zip(b.origin.translation.toSeq).forall { case (x, y) => close(x, y, 1) } &&
      a.origin.rotation.rows.flatten.zip(b.origin.rotation.rows.flatten).forall { case (x, y) =>
        close(x, y, 1)
      }
    }
    if (chain.size != g.expected.size || !shape)
      return Failed(s"$label: the chain read differs from the one written")
    val warned = chain.warnings.map(_.where)
    if (warned.size != g.bareLinks.size || !g.bareLinks.forall(l => warned.contains(s"$file: link '$l'")))
      return Failed(
        s"$label: warnings ${warned.mkString(", ")}; expected one per link ${g.bareLinks.mkString(", ")}"
      )
    g.prismatic match {
      case Some(joint) =>
        // Not compiled yet: refused through the command line, naming the file and the joint.
        refusedCleanly(file, g.tip, dir.resolve("out")) match {
          case Right(line) if line.contains(joint) && line.contains("prismatic") => Refused(s"$label: $line")
          case Right(line) => Failed(s"$label: prismatic $joint refused with: $line")
          case Left(why)   => Failed(s"$label: prismatic $joint: $why")
        }
      case None => checkDynamics(rng, g, file, chain, label)
    }
  }

  private def checkDynamics(
      rng: Random,
      g: GeneratedUrdf,
      file: Path,
      chain: SerialChain,
      label: String
  ): FuzzOutcome = {
    val n = chain.size
    val vmax = chain.joints.map(_.velocityLimit.get)
    val amax = Seq.fill(n)(maxAcceleration)
    val samples = Seq.fill(samplesPerChain)(RandomChains.sample(rng, vmax, amax))
    // RNEA on the merged bodies against Euler-Lagrange on every link apart.
    val lagrange = samples.map { case (q, qd, qdd) =>
      val a = Rnea.reference(chain, q, qd, qdd)
      val b = LagrangeReference.torques(g.expected, g.bodies, q, qd, qdd, 1e-6)
      val scale = b.map(math.abs).max
      a.zip(b).map { case (x, y) => math.abs(x - y) / (1 + scale) }.max
    }.max
    if (!(lagrange < 1e-6))
      return Failed(f"$label: RNEA and Euler-Lagrange differ by $lagrange%.2e (relative)")
    val params = LoadParams.arm.copy(
      robot = RobotParams(source = file.toString, tip = g.tip, maxVelocity = Nil, maxAcceleration = amax),
      schedule = oneClock
    )
    val arm =
      try Compiler.compile(params, "fuzz").arm
      catch {
        // Heavy links at full speed on every joint at once can need wider torques than the preset's formats.
        case e: InputError if e.getMessage.contains(Capacity) => return Refused(s"$label: ${e.getMessage}")
        case e: InputError => return Failed(s"$label: a valid robot not compiled: ${e.getMessage}")
      }
    val model = new ArmModel(arm)
    val worst = samples.map { case (q, qd, qdd) =>
      val hw = model.evaluate(ArmSample(q, qd, qdd))
      val ref = Rnea.reference(chain, q, qd, qdd)
      hw.indices.map(j => math.abs(hw(j) - ref(j)) / arm.errorBounds(j)).max
    }.max
    if (!(worst <= 1)) Failed(f"$label: the model's error is ${worst * 100}%.0f%% of its derived bound")
    else
      Passed(
        f"$label: RNEA = Lagrange to $lagrange%.1e, model at ${worst * 100}%.0f%% of its bound (${arm.errorBound}%.1e N·m)"
      )
  }

  /** Counts of a run and its failures (case number, outcome). */
  final case class Summary(cases: Int, passed: Int, refused: Int, failures: Seq[(Int, Failed)]) {
    def table(seed: Long): String = (Seq(
      "| cases tried | valid passed | refused cleanly | failures |",
      "| --- | --- | --- | --- |",
      s"| $cases | $passed | $refused | ${failures.size} |"
    ) ++ failures.map { case (i, f) =>
      s"failure: case $i (rerun: ./sbt \"Test/runMain reducerload.robot.UrdfFuzz --seed $seed --case $i\"): ${f.detail}"
    }).mkString("\n")
  }

  def runAll(
      seed: Long,
      cases: Seq[Int],
      dir: Path,
      progress: (Int, FuzzOutcome, Double) => Unit = (_, _, _) => ()
  ): Summary = {
    val outcomes = cases.map { i =>
      val start = System.nanoTime()
      val o = run(seed, i, dir)
      progress(i, o, (System.nanoTime() - start) / 1e9)
      i -> o
    }
    Summary(
      cases.size,
      outcomes.count(_._2.isInstanceOf[Passed]),
      outcomes.count(_._2.isInstanceOf[Refused]),
      outcomes.collect { case (i, f: Failed) => i -> f }
    )
  }

  def main(args: Array[String]): Unit = {
    def arg(name: String) = args.sliding(2).collectFirst { case Array(`name`, v) => v }
    val seed = arg("--seed").map(_.toLong).getOrElse(1L)
    val cases =
      arg("--case").map(c => Seq(c.toInt)).getOrElse(0 until arg("--cases").map(_.toInt).getOrElse(2000))
    val verbose = args.contains("--verbose") || cases.size == 1
    val dir = Files.createTempDirectory("urdf-fuzz-")
    val start = System.nanoTime()
    println(s"[urdf-fuzz] seed $seed, ${cases.size} cases")
    val summary = runAll(
      seed,
      cases,
      dir,
      (i, o, seconds) => {
        if (verbose || o.isInstanceOf[Failed]) println(f"case $i ($seconds%.2f s): $o")
        if ((i + 1) % 100 == 0)
          println(s"[urdf-fuzz] ${i + 1} cases, ${(System.nanoTime() - start) / 1000000000} s")
      }
    )
    VerilatorHarness.deleteTree(dir)
    println(summary.table(seed))
    println(f"[urdf-fuzz] ${(System.nanoTime() - start) / 1e9}%.0f s")
    if (summary.failures.nonEmpty) sys.exit(1)
  }
}
