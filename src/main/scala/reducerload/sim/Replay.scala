package reducerload.sim

import java.io.OutputStream
import java.nio.charset.StandardCharsets
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
  def chunkSize(engine: ReplayEngine, samples: Int, jobs: Int): Int = {
    val most = engine match {
      case ReplayEngine.Rtl(_) => 1 << 16
      case ReplayEngine.Model  => 1 << 12
    }
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

  /** Outputs of `inputs` on `engine`, and the harness run's figures for the RTL. */
  def outputs[In, Out](
      design: ReplayDesign[In, Out],
      engine: ReplayEngine,
      inputs: IndexedSeq[In]
  ): (IndexedSeq[Out], Option[HarnessStats]) =
    engine match {
      case ReplayEngine.Model => (inputs.map(design.evaluate), None)
      case ReplayEngine.Rtl(harness) =>
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

  /** Run every row, write the header and one line per sample to `out`. */
  def run[In, Out](
      design: ReplayDesign[In, Out],
      engine: ReplayEngine,
      rows: SampleRows,
      jobs: Int,
      out: OutputStream,
      progress: ProgressLine
  ): ReplaySummary = {
    val start = System.nanoTime()
    val labels = design.errorLabels.size
    out.write((design.outputHeader + "\n").getBytes(StandardCharsets.UTF_8))
    design.arrays match {
      case Some(fast) => return runArrays(design, fast, engine, rows, jobs, out, progress, start)
      case None       =>
    }
    val size = chunkSize(engine, rows.size, jobs)
    val writer = new InOrderWriter(out, (rows.size + size - 1) / size)
    val chunks = ChunkedRun(rows.size, size, jobs, n => progress.advance(n.toLong)) { range =>
      val cpuStart = threads.getCurrentThreadCpuTime
      val (outs, harnessStats) = outputs(design, engine, range.map(i => design.encode(rows.row(i))))
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
    ReplaySummary(
      rows.size.toLong,
      (0 until labels).map(j => chunks.map(_.maxErrors(j)).maxOption.getOrElse(0.0)),
      chunks.map(_.outOfRange).sum,
      (System.nanoTime() - start) / 1e9,
      chunks.map(_.cpuSeconds).sum,
      chunks.flatMap(_.harness)
    )
  }

  /** [[run]] on the design's [[ArrayReplay]]: the same lines, from codes and outputs in long arrays. */
  private def runArrays(
      design: ReplayDesign[_, _],
      fast: ArrayReplay,
      engine: ReplayEngine,
      rows: SampleRows,
      jobs: Int,
      out: OutputStream,
      progress: ProgressLine,
      start: Long
  ): ReplaySummary = {
    val labels = design.errorLabels.size
    val size = engine match {
      case ReplayEngine.Model => ((rows.size + jobs - 1) / jobs).min(1 << 14).max(1)
      case _                  => chunkSize(engine, rows.size, jobs)
    }
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
      val harnessStats = engine match {
        case ReplayEngine.Model =>
          k = 0
          while (k < n) { worker.evaluate(codes, k * ins, results, k * outs); k += 1 }
          None
        case ReplayEngine.Rtl(harness) =>
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
    ReplaySummary(
      rows.size.toLong,
      (0 until labels).map(j => chunks.map(_.maxErrors(j)).maxOption.getOrElse(0.0)),
      chunks.map(_.outOfRange).sum,
      (System.nanoTime() - start) / 1e9,
      chunks.map(_.cpuSeconds).sum,
      chunks.flatMap(_.harness),
      chunks.flatMap(_.phases).reduceOption(_ + _)
    )
  }
}
