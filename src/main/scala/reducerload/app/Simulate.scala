package reducerload.app

import chiseltest.RawTester
import chiseltest.simulator.VerilatorBackendAnnotation
import reducerload.arm.{ArmConfig, ArmDatapath, ArmModel, ArmOutputCodes, ArmParams, ArmSample, ArmTrajectory}
import reducerload.dynamics.Rnea
import reducerload.graph.SampleCodes
import reducerload.load._
import reducerload.sim.{ArmDriver, Cycle, LoadDriver, Stream}
import reducerload.trace.{InputError, TraceCsv}

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path, StandardCopyOption}
import scala.sys.process._
import scala.util.Try

/** `run simulate`: a user's trajectory through the generated RTL on Verilator, as fast as the design takes samples. */
object Simulate {
  val options: Seq[Opt] = Seq(
    Opt("input", "FILE", "trajectory CSV: header t1,t2,t3,d1,d2,d3,dd1,dd2,dd3 (joint 3), or q1..qN,qd1..qdN,qdd1..qddN (model rnea); rad, rad/s, rad/s^2"),
    Opt("output", "FILE", "result CSV: idx,load_hw,load_ref,error,out_of_range, or idx,tauJ_hw,tauJ_ref,tauJ_error...,out_of_range (N·m)")
  )
  val flags: Seq[String] = Seq("saturate")
  val flagHelp: Map[String, String] = Map(
    "saturate" -> "accept values beyond the declared ranges: the hardware clamps them and flags the sample; count them"
  )

  /** Rows beyond the declared ranges: (line, column, value, limit). */
  def outOfRange(p: LoadParams, rows: IndexedSeq[(Int, JointSample)]): Seq[(Int, String, Double, Double)] =
    rows.flatMap { case (line, s) =>
      val limits = p.robot.maxVelocity ++ p.robot.maxAcceleration
      Seq("d1", "d2", "d3", "dd1", "dd2", "dd3").zip(Seq(s.d1, s.d2, s.d3, s.dd1, s.dd2, s.dd3)).zip(limits).collect {
        case ((col, v), lim) if math.abs(v) > lim => (line, col, v, lim)
      }
    }

  def readTrajectory(path: Path): IndexedSeq[(Int, JointSample)] = {
    val table = TraceCsv.read(path, JointSample.columns)
    val cols = JointSample.columns.map(table.column)
    table.rows.indices.map(i => table.rows(i)._1 -> JointSample.fromSeq(cols.map(_(i))))
  }

  /** Run `body` with a scratch build directory under target/ (chiseltest wants a relative one), removed afterwards. */
  private def inScratch[T](body: Seq[firrtl2.annotations.Annotation] => T): T = {
    val scratch = java.nio.file.Paths.get("target", "simulate")
    Files.createDirectories(scratch)
    val dir = java.nio.file.Paths.get("").toAbsolutePath.relativize(Files.createTempDirectory(scratch.toAbsolutePath, "run-"))
    try body(Seq(VerilatorBackendAnnotation, firrtl2.options.TargetDirAnnotation(dir.toString)))
    finally Try(Seq("rm", "-rf", dir.toString).!)
  }

  /** Run the RTL: returns outputs in sample order and the wall-clock samples per second of the simulation. */
  def simulate(p: LoadParams, codes: IndexedSeq[LoadInputCodes]): (IndexedSeq[LoadOutputCodes], Double) = inScratch { annotations =>
    val outputs = Vector.newBuilder[LoadOutputCodes]
    val seconds = new java.util.concurrent.atomic.AtomicLong // nanoseconds, set inside the simulator callback
    RawTester.test(new LoadDatapath(p), annotations) { dut =>
      val stimulus = Stream.spaced(codes.iterator.map(Cycle.Sample(_)), p.samplePeriod) ++ Iterator.fill(dut.latency + 1)(Cycle.Bubble)
      val start = System.nanoTime()
      LoadDriver.run(dut, stimulus, (_, out) => out.foreach(outputs += _))
      seconds.set(System.nanoTime() - start)
    }
    (outputs.result(), codes.size / (seconds.get / 1e9).max(1e-9))
  }

  /** Run an arm's RTL, one sample per clock: outputs in sample order and samples per second. */
  def simulateArm(p: ArmParams, codes: IndexedSeq[SampleCodes]): (IndexedSeq[ArmOutputCodes], Double) = inScratch { annotations =>
    val outputs = Vector.newBuilder[ArmOutputCodes]
    val seconds = new java.util.concurrent.atomic.AtomicLong
    RawTester.test(new ArmDatapath(p), annotations) { dut =>
      val stimulus = codes.iterator.map(Cycle.Sample(_)) ++ Iterator.fill(p.latency + 1)(Cycle.Bubble)
      val start = System.nanoTime()
      ArmDriver.run(dut, stimulus, (_, out) => out.foreach(outputs += _))
      seconds.set(System.nanoTime() - start)
    }
    (outputs.result(), codes.size / (seconds.get / 1e9).max(1e-9))
  }

  /** Every check of the command line and the input file, before any simulation: (params, rows, output). */
  def prepare(cli: Cli): (LoadParams, IndexedSeq[(Int, JointSample)], Path) = {
    val input = cli.path("input").getOrElse(throw new InputError("command line: simulate needs --input FILE"))
    val output = cli.path("output").getOrElse(throw new InputError("command line: simulate needs --output FILE"))
    val p = cli.params
    val rows = readTrajectory(input)
    val beyond = outOfRange(p, rows)
    if (beyond.nonEmpty && !cli.has("saturate")) {
      val (line, col, v, lim) = beyond.head
      throw new InputError(s"$input:$line: column '$col': $v is beyond the declared range |$col| <= $lim " +
        s"(${beyond.size} value(s) in all; --saturate clamps and counts them, or widen the range)")
    }
    (p, rows, output)
  }

  def run(cli: Cli): Unit = {
    val design = cli.params
    if (!design.model.closedForm) runArm(cli, ArmConfig(design))
    else runJoint3(cli)
  }

  private def requireVerilator(): Unit =
    if (Try(Seq("verilator", "--version").!!(ProcessLogger(_ => ()))).isFailure)
      throw new InputError("simulate needs Verilator on the PATH (Debian: apt-get install verilator)")

  /** Every joint of an arm: header q1..qn,qd1..qdn,qdd1..qddn; checks before anything runs. */
  private def runArm(cli: Cli, p: ArmParams): Unit = {
    val input = cli.path("input").getOrElse(throw new InputError("command line: simulate needs --input FILE"))
    val output = cli.path("output").getOrElse(throw new InputError("command line: simulate needs --output FILE"))
    val n = p.chain.size
    val columns = ArmTrajectory.columns(n)
    val table = TraceCsv.read(input, columns)
    val cols = columns.map(table.column)
    val rows = table.rows.indices.map { i =>
      val v = cols.map(_(i))
      table.rows(i)._1 -> ArmSample(v.slice(0, n).toIndexedSeq, v.slice(n, 2 * n).toIndexedSeq, v.slice(2 * n, 3 * n).toIndexedSeq)
    }
    val beyond = rows.flatMap { case (line, s) =>
      (0 until n).flatMap { j =>
        Seq((s"qd${j + 1}", s.qd(j), p.numerics.velocityLimits(j)), (s"qdd${j + 1}", s.qdd(j), p.numerics.accelerationLimits(j)))
          .collect { case (col, v, lim) if math.abs(v) > lim => (line, col, v, lim) }
      }
    }
    if (beyond.nonEmpty && !cli.has("saturate")) {
      val (line, col, v, lim) = beyond.head
      throw new InputError(s"$input:$line: column '$col': $v is beyond the declared range |$col| <= $lim " +
        s"(${beyond.size} value(s) in all; --saturate clamps and counts them, or widen the range)")
    }
    requireVerilator()
    val model = new ArmModel(p)
    val (outs, rate) = simulateArm(p, rows.map { case (_, s) => model.encode(s) })
    if (outs.size != rows.size) throw new IllegalStateException(s"the RTL returned ${outs.size} results for ${rows.size} samples")
    val results = rows.zip(outs).map { case ((_, s), o) =>
      (model.torques(o), Rnea.reference(p.chain, s.q, s.qd, s.qdd), o.outOfRange.exists(identity))
    }
    val header = "idx" +: (1 to n).flatMap(j => Seq(s"tau${j}_hw", s"tau${j}_ref", s"tau${j}_error")) :+ "out_of_range"
    val lines = results.zipWithIndex.map { case ((hw, ref, oor), i) =>
      (i.toString +: (0 until n).flatMap(j => Seq(hw(j).toString, ref(j).toString, (hw(j) - ref(j)).toString)) :+ (if (oor) "1" else "0")).mkString(",")
    }
    writeAtomically(output, (header.mkString(",") +: lines).mkString("", "\n", "\n"))
    val inRange = results.filterNot(_._3)
    println(s"wrote $output: ${rows.size} samples, robot ${p.chain.name} ($n joints), every joint by RNEA")
    val worst = (0 until n).map { j =>
      val err = inRange.map(r => math.abs(r._1(j) - r._2(j))).maxOption.getOrElse(0.0)
      println(f"  ${p.jointNames(j)}%-24s max |error| $err%.3e N·m (derived bound ${p.errorBounds(j)}%.3e N·m)")
      (err, p.errorBounds(j))
    }
    println(s"out-of-range samples (clamped, flagged): ${results.count(_._3)}")
    println(f"simulation rate: $rate%.0f samples/s (Verilator, one sample per clock, latency ${p.latency} cycles)")
    worst.zipWithIndex.find { case ((e, b), _) => e > b }.foreach { case ((e, b), j) =>
      throw new IllegalStateException(s"joint ${j + 1}: max error $e exceeds the derived bound $b")
    }
  }

  private def runJoint3(cli: Cli): Unit = {
    val (p, rows, output) = prepare(cli)
    requireVerilator()
    val model = new LoadDatapathModel(p)
    val codes = rows.map { case (_, s) => model.encode(s) }
    val (outs, rate) = simulate(p, codes)
    if (outs.size != rows.size)
      throw new IllegalStateException(s"the RTL returned ${outs.size} loads for ${rows.size} samples")
    val results = rows.zip(outs).map { case ((_, s), o) =>
      val hw = model.loadOf(o)
      val ref = LoadReference.torque(p.robot, p.model, s)
      (hw, ref, hw - ref, o.outOfRange)
    }
    val text = ("idx,load_hw,load_ref,error,out_of_range" +: results.zipWithIndex.map { case ((hw, ref, err, oor), i) =>
      s"$i,$hw,$ref,$err,${if (oor) 1 else 0}"
    }).mkString("", "\n", "\n")
    writeAtomically(output, text)
    val inRange = results.filterNot(_._4)
    val maxErr = inRange.map(r => math.abs(r._3)).maxOption.getOrElse(0.0)
    println(s"wrote $output: ${rows.size} samples, model ${p.model.name}")
    println(f"max |error| over in-range samples: $maxErr%.3e N·m (derived bound ${p.errorBound}%.3e N·m)")
    println(s"out-of-range samples (clamped, flagged): ${results.count(_._4)}")
    println(f"simulation rate: $rate%.0f samples/s (Verilator, ${Report.throughput(p)}, latency ${LoadDatapath.latency(p)} cycles)")
    if (maxErr > p.errorBound) throw new IllegalStateException(s"max error $maxErr exceeds the derived bound ${p.errorBound}")
  }

  def writeAtomically(path: Path, text: String): Unit = {
    val abs = path.toAbsolutePath.normalize
    val parent = abs.getParent
    if (parent != null && !Files.isDirectory(parent)) throw new InputError(s"$path: directory ${parent} does not exist")
    val tmp = Files.createTempFile(parent, ".partial-", ".csv")
    try {
      Files.write(tmp, text.getBytes(StandardCharsets.UTF_8))
      Files.move(tmp, abs, StandardCopyOption.REPLACE_EXISTING, StandardCopyOption.ATOMIC_MOVE)
    } finally Files.deleteIfExists(tmp)
  }
}
