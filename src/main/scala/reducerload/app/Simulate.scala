package reducerload.app

import chiseltest.RawTester
import chiseltest.simulator.VerilatorBackendAnnotation
import reducerload.load._
import reducerload.sim.{Cycle, LoadDriver, Stream}
import reducerload.trace.{InputError, TraceCsv}

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path, StandardCopyOption}
import scala.sys.process._
import scala.util.Try

/** `run simulate`: a user's trajectory through the generated RTL on Verilator, as fast as the design takes samples. */
object Simulate {
  val options: Seq[Opt] = Seq(
    Opt("input", "FILE", "trajectory CSV with header t1,t2,t3,d1,d2,d3,dd1,dd2,dd3 (rad, rad/s, rad/s^2)"),
    Opt("output", "FILE", "result CSV: idx,load_hw,load_ref,error,out_of_range (N·m)")
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

  /** Run the RTL: returns outputs in sample order and the wall-clock samples per second of the simulation. */
  def simulate(p: LoadParams, codes: IndexedSeq[LoadInputCodes]): (IndexedSeq[LoadOutputCodes], Double) = {
    // chiseltest wants a relative build directory: a scratch folder under target/, removed afterwards.
    val scratch = java.nio.file.Paths.get("target", "simulate")
    Files.createDirectories(scratch)
    val dir = java.nio.file.Paths.get("").toAbsolutePath.relativize(Files.createTempDirectory(scratch.toAbsolutePath, "run-"))
    val outputs = Vector.newBuilder[LoadOutputCodes]
    val rate = try {
      val annotations = Seq(VerilatorBackendAnnotation, firrtl2.options.TargetDirAnnotation(dir.toString))
      var seconds = 0.0 // set once, inside the simulator callback
      RawTester.test(new LoadDatapath(p), annotations) { dut =>
        val stimulus = Stream.spaced(codes.iterator.map(Cycle.Sample(_)), p.samplePeriod) ++ Iterator.fill(dut.latency + 1)(Cycle.Bubble)
        val start = System.nanoTime()
        LoadDriver.run(dut, stimulus, (_, out) => out.foreach(outputs += _))
        seconds = (System.nanoTime() - start) / 1e9
      }
      codes.size / seconds.max(1e-9)
    } finally {
      Try(Seq("rm", "-rf", dir.toString).!)
    }
    (outputs.result(), rate)
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
    val (p, rows, output) = prepare(cli)
    if (Try(Seq("verilator", "--version").!!(ProcessLogger(_ => ()))).isFailure)
      throw new InputError("simulate needs Verilator on the PATH (Debian: apt-get install verilator)")
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
