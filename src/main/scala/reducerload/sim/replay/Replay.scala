package reducerload.sim.replay

import reducerload.sim.rtl.{CompiledHarness, HarnessStats}
import reducerload.util.ChunkedRun

import java.io.{OutputStream, PrintStream}
import java.nio.charset.StandardCharsets
import java.util.concurrent.atomic.{AtomicBoolean, AtomicLong}
import scala.collection.mutable.ArrayBuffer

/**
 * A trajectory through a [[ReplayDesign]] on an engine, in chunks on `jobs` threads: each chunk converts its
 * rows, runs them (a harness process from reset, or the model), and formats its result lines; the lines are
 * written in sample order while later chunks run. The datapath keeps no state between samples, so the file
 * does not depend on the chunking.
 */
object Replay {

  /**
   * Samples per chunk: a harness process each (start-up is milliseconds), or a model batch; at least one
   * chunk per job, so short runs use every job too.
   */
  def chunkSize(harness: Option[CompiledHarness], samples: Int, jobs: Int): Int = {
    val most = if (harness.isDefined) 1 << 16 else 1 << 12
    ((samples + jobs - 1) / jobs).min(most).max(1)
  }

  private final case class ChunkResult(
      maxErrors: Array[Double],
      outOfRange: Long,
      harness: Option[HarnessStats],
      cpuSeconds: Double,
      phases: Option[ReplayPhases] = None
  )

  private val threads = java.lang.management.ManagementFactory.getThreadMXBean

  /** The chunks' figures merged: the largest error per label, the sums, and the phases where measured. */
  private def summary(samples: Long, labels: Int, chunks: Seq[ChunkResult], start: Long) = ReplaySummary(
    samples,
    (0 until labels).map(j => chunks.map(_.maxErrors(j)).maxOption.getOrElse(0.0)),
    chunks.map(_.outOfRange).sum,
    (System.nanoTime() - start) / 1e9,
    chunks.map(_.cpuSeconds).sum,
    chunks.flatMap(_.harness),
    chunks.flatMap(_.phases).reduceOption(_ + _)
  )

  /**
   * Outputs of `inputs` on the RTL's compiled `harness` (and the harness run's figures), or with None on the
   * bit-accurate model.
   */
  def outputs[In, Out](
      design: ReplayDesign[In, Out],
      harness: Option[CompiledHarness],
      inputs: IndexedSeq[In]
  ): (IndexedSeq[Out], Option[HarnessStats]) =
    harness match {
      case None => (inputs.map(design.evaluate), None)
      case Some(harness) =>
        val outs = new ArrayBuffer[Out](inputs.size)
        val stats =
          harness.stream(inputs.iterator.map(design.harnessValues), design.samplePeriod, design.latency + 1)(
            (_, values) => outs += design.fromHarness(values)
          )
        if (outs.size != inputs.size)
          throw new IllegalStateException(s"the RTL returned ${outs.size} results for ${inputs.size} samples")
        (outs.toIndexedSeq, Some(stats))
    }

  /**
   * Texts of numbered chunks to `out` in chunk order, as soon as each one and every one before it is there:
   * writing overlaps the work on later chunks, and at most the chunks done out of order wait.
   */
  private final class InOrderWriter(out: OutputStream, count: Int) {
    private val waiting = new Array[Array[Byte]](count)
    private var next = 0 // guarded by this

    def put(k: Int, text: Array[Byte]): Unit = synchronized {
      waiting(k) = text
      while (next < count && waiting(next) != null) {
        out.write(waiting(next))
        waiting(next) = null
        next += 1
      }
    }
  }

  /** The text of a chunk's lines (ASCII: numbers, commas, line ends) as bytes. */
  private def bytes(text: java.lang.StringBuilder): Array[Byte] =
    text.toString.getBytes(StandardCharsets.ISO_8859_1)

  /**
   * Run every row on the RTL's compiled `harness` (one process per chunk, started from reset) or, with None,
   * on the bit-accurate model; write the header and one line per sample to `out`.
   */
  def run[In, Out](
      design: ReplayDesign[In, Out],
      harness: Option[CompiledHarness],
      rows: SampleRows,
      jobs: Int,
      out: OutputStream,
      progress: ProgressLine
  ): ReplaySummary = {
    val start = System.nanoTime()
    val labels = design.errorLabels.size
    out.write((design.outputHeader + "\n").getBytes(StandardCharsets.UTF_8))
    design.arrays match {
      case Some(fast) => return runArrays(design, fast, harness, rows, jobs, out, progress, start)
      case None       =>
    }
    val size = chunkSize(harness, rows.size, jobs)
    val writer = new InOrderWriter(out, (rows.size + size - 1) / size)
    val chunks = ChunkedRun(rows.size, size, jobs, n => progress.advance(n.toLong)) { range =>
      val cpuStart = threads.getCurrentThreadCpuTime
      val (outs, harnessStats) = outputs(design, harness, range.map(i => design.encode(rows.row(i))))
      val text = new java.lang.StringBuilder(range.size * 96)
      val maxErrors = new Array[Double](labels)
      val errors = new Array[Double](labels)
      val flagged = range.indices.count { k =>
        val outOfRange = design.result(range(k).toLong, rows.row(range(k)), outs(k), text, errors)
        text.append('\n')
        if (!outOfRange) errors.indices.foreach(j => maxErrors(j) = maxErrors(j).max(errors(j)))
        outOfRange
      }
      val cpuSeconds = (threads.getCurrentThreadCpuTime - cpuStart) / 1e9
      writer.put(range.start / size, bytes(text))
      ChunkResult(maxErrors, flagged.toLong, harnessStats, cpuSeconds)
    }
    progress.finish()
    summary(rows.size.toLong, labels, chunks, start)
  }

  /** [[run]] on the design's [[ArrayReplay]]: the same lines, from codes and outputs in long arrays. */
  private def runArrays(
      design: ReplayDesign[_, _],
      fast: ArrayReplay,
      harness: Option[CompiledHarness],
      rows: SampleRows,
      jobs: Int,
      out: OutputStream,
      progress: ProgressLine,
      start: Long
  ): ReplaySummary = {
    val labels = design.errorLabels.size
    val size =
      if (harness.isEmpty) ((rows.size + jobs - 1) / jobs).min(1 << 14).max(1)
      else chunkSize(harness, rows.size, jobs)
    val (ins, outs) = (fast.inputCount, fast.outputCount)
    val workers = ThreadLocal.withInitial[ArrayReplay.Worker](() => fast.worker())
    val writer = new InOrderWriter(out, (rows.size + size - 1) / size)
    val chunks = ChunkedRun(rows.size, size, jobs, n => progress.advance(n.toLong)) { range =>
      val cpuStart = threads.getCurrentThreadCpuTime
      val codesStart = System.nanoTime()
      val worker = workers.get()
      val n = range.size
      val first = range.start
      val codes = new Array[Long](n * ins)
      var k = 0
      val values = rows.values
      while (k < n) { worker.encode(values, rows.offset(first + k), codes, k * ins); k += 1 }
      val engineStart = System.nanoTime()
      val results = new Array[Long](n * outs)
      val harnessStats = harness match {
        case None =>
          k = 0
          while (k < n) { worker.evaluate(codes, k * ins, results, k * outs); k += 1 }
          None
        case Some(harness) =>
          Some(harness.streamLongs(codes, n, design.samplePeriod, design.latency + 1)(results))
      }
      val linesStart = System.nanoTime()
      val text = new java.lang.StringBuilder(n * (24 + 60 * labels))
      val maxErrors = new Array[Double](labels)
      val errors = new Array[Double](labels)
      var flagged = 0L
      k = 0
      while (k < n) {
        val i = first + k
        if (worker.result(i.toLong, values, rows.offset(i), results, k * outs, text, errors)) flagged += 1
        else { var j = 0; while (j < labels) { maxErrors(j) = maxErrors(j).max(errors(j)); j += 1 } }
        text.append('\n')
        k += 1
      }
      val text8 = bytes(text)
      val linesEnd = System.nanoTime()
      val cpuSeconds = (threads.getCurrentThreadCpuTime - cpuStart) / 1e9
      writer.put(first / size, text8)
      ChunkResult(
        maxErrors,
        flagged,
        harnessStats,
        cpuSeconds,
        Some(
          ReplayPhases(
            (engineStart - codesStart) / 1e9,
            (linesStart - engineStart) / 1e9,
            (linesEnd - linesStart) / 1e9
          )
        )
      )
    }
    progress.finish()
    summary(rows.size.toLong, labels, chunks, start)
  }
}

/** What computes a replay's outputs, by its name on the command line (`--engine`). */
sealed abstract class ReplayEngine(val name: String)
object ReplayEngine {

  /** The emitted RTL on a compiled Verilator harness. */
  case object Rtl extends ReplayEngine("rtl")

  /** The bit-accurate model: for replays where the RTL has been proven equal to it. */
  case object Model extends ReplayEngine("model")

  val all: Seq[ReplayEngine] = Seq(Rtl, Model)
  def named(name: String): Option[ReplayEngine] = all.find(_.name == name)
}

/**
 * What a replay found: max |error| per `errorLabels` entry over in-range samples, the samples flagged out of
 * range, the wall-clock seconds of the run (conversion, engine, result lines), the JVM threads' CPU seconds
 * (summed over jobs; on a shared machine the wall clock also counts other work), for the RTL every harness
 * process's figures, and where the replay runs in arrays the time of each of its phases.
 */
final case class ReplaySummary(
    samples: Long,
    maxErrors: IndexedSeq[Double],
    outOfRange: Long,
    seconds: Double,
    cpuSeconds: Double,
    harness: Seq[HarnessStats],
    phases: Option[ReplayPhases] = None
) {
  def samplesPerSecond: Double = samples / seconds.max(1e-9)
  def samplesPerCpuSecond: Double = samples / cpuSeconds.max(1e-9)
  def harnessCycles: Long = harness.map(_.cycles).sum

  /**
   * Clocks per second of harness process wall time (summed over processes), and per second of their CPU time.
   */
  def cyclesPerHarnessSecond: Double = harnessCycles / harness.map(_.seconds).sum.max(1e-9)
  def cyclesPerHarnessCpuSecond: Double = harnessCycles / harness.map(_.cpuSeconds).sum.max(1e-9)
}

/**
 * Wall-clock seconds of a replay's phases, summed over its jobs: the input codes, the engine (the
 * bit-accurate model, or a harness process with its input and output files) and the result lines (the
 * double-precision reference and the text). The engine's figure is what the engine alone takes per sample,
 * apart from the conversion and the file's text around it.
 */
final case class ReplayPhases(codes: Double, engine: Double, lines: Double) {
  def +(o: ReplayPhases): ReplayPhases = ReplayPhases(codes + o.codes, engine + o.engine, lines + o.lines)
}

/**
 * Samples done, rate and time left of a long run, on one line rewritten at most once a second. Thread-safe:
 * chunks finishing on several threads call [[advance]]. Quiet when `out` is None.
 */
final class ProgressLine(total: Long, what: String, out: Option[PrintStream]) {
  private val start = System.nanoTime()
  private val done = new AtomicLong
  private val lastShown = new AtomicLong(start)
  private val shown = new AtomicBoolean(false) // whether a line needs clearing at the end

  def advance(samples: Long): Unit = {
    val now = System.nanoTime()
    val d = done.addAndGet(samples)
    val last = lastShown.get
    if (out.isDefined && now - last >= 1000000000L && lastShown.compareAndSet(last, now)) out.foreach { o =>
      val rate = d / ((now - start) / 1e9)
      val left = if (rate > 0) (total - d) / rate else 0.0
      o.print(f"\r$what: $d%d of $total%d samples, $rate%.0f samples/s, ${left}%.0f s left   ")
      o.flush()
      shown.set(true)
    }
  }

  /** Clear the line, so the summary that follows starts clean. */
  def finish(): Unit = if (shown.get) out.foreach { o => o.print("\r" + " " * 100 + "\r"); o.flush() }
}

object ProgressLine {

  /** On a terminal only: a redirected or piped run (a log, a test) stays quiet. */
  def onTerminal(total: Long, what: String): ProgressLine =
    new ProgressLine(total, what, if (System.console() != null) Some(System.out) else None)
}
