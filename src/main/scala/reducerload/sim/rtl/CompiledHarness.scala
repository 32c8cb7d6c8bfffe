package reducerload.sim.rtl

import java.nio.channels.FileChannel
import java.nio.file.{Files, Path, StandardOpenOption}
import java.nio.{ByteBuffer, ByteOrder}
import scala.collection.immutable.ArraySeq
import scala.collection.mutable.ArrayBuffer
import scala.sys.process._

/**
 * A built Verilator harness (see [[VerilatorHarness.compile]]). Each run streams the samples to a binary file
 * in a temporary directory, runs the executable, and reads its binary outputs back; the directory is removed
 * afterwards.
 */
final class CompiledHarness(val executable: Path, val ports: HarnessPorts, val fromCache: Boolean) {

  /** The cache entry: executable, design.sv, harness.cpp and build.log. */
  def directory: Path = executable.getParent

  private val outputPorts = ports.outputs.toArray
  private val inputPorts = ports.inputs.toArray
  private val inRecord = 8 * ports.inputs.size
  private val outRecord = 8 * (1 + ports.outputs.size)

  /**
   * Run every sample of `inputs` (values in the order of `ports.inputs`), at most one every `samplePeriod`
   * clocks and only when the design is ready, then `drainCycles` more clocks so the last outputs come out (at
   * least the design's latency). Outputs go to `onOutput(cycle, values)` as they are read back, so memory
   * stays constant however long the stream.
   */
  def stream(
      inputs: Iterator[Seq[BigInt]],
      samplePeriod: Int = 1,
      drainCycles: Int = 256,
      maxStallCycles: Long = 1000000L
  )(
      onOutput: (Long, IndexedSeq[BigInt]) => Unit,
      onAccepted: Long => Unit = _ => ()
  ): HarnessStats = {
    require(samplePeriod >= 1, s"harness: samplePeriod must be >= 1, got $samplePeriod")
    require(drainCycles >= 0, s"harness: drainCycles must be >= 0, got $drainCycles")
    require(maxStallCycles >= 0, s"harness: maxStallCycles must be >= 0, got $maxStallCycles")
    runProcess(samplePeriod, drainCycles, maxStallCycles)(writeInputs(_, inputs)) { (out, accepted) =>
      val outputs = readRecords(out, outRecord) { b =>
        val cycle = b.getLong()
        val values = new Array[BigInt](outputPorts.length)
        var i = 0
        while (i < values.length) { values(i) = decode(outputPorts(i), b.getLong()); i += 1 }
        onOutput(cycle, ArraySeq.unsafeWrapArray(values))
      }
      (outputs, readRecords(accepted, 8)(b => onAccepted(b.getLong())))
    }
  }

  /**
   * [[stream]] of the `count` samples in `inputs` (`ports.inputs.size` values each, in port order), every
   * output to `outputs` (`ports.outputs.size` values each; ports of at most 63 bits); there must be one
   * output per sample. No allocation per sample.
   */
  def streamLongs(
      inputs: Array[Long],
      count: Int,
      samplePeriod: Int,
      drainCycles: Int,
      maxStallCycles: Long = 1000000L
  )(outputs: Array[Long]): HarnessStats = {
    require(samplePeriod >= 1, s"harness: samplePeriod must be >= 1, got $samplePeriod")
    require(drainCycles >= 0, s"harness: drainCycles must be >= 0, got $drainCycles")
    require(maxStallCycles >= 0, s"harness: maxStallCycles must be >= 0, got $maxStallCycles")
    require(
      outputPorts.forall(p => p.width <= 63 || p.signed),
      "harness: streamLongs needs output ports of at most 63 bits (or signed)"
    )
    val width = inputPorts.length
    val outWidth = outputPorts.length
    require(
      inputs.length >= count * width && outputs.length >= count * outWidth,
      s"harness: arrays too short for $count samples"
    )
    runProcess(samplePeriod, drainCycles, maxStallCycles) { path =>
      val channel = FileChannel.open(path, StandardOpenOption.CREATE_NEW, StandardOpenOption.WRITE)
      try {
        val buffer = ByteBuffer.allocate(inRecord * 8192).order(ByteOrder.LITTLE_ENDIAN)
        val (min, max) = (inputMin, inputMax)
        var k = 0
        while (k < count) {
          if (buffer.remaining < inRecord) {
            buffer.flip(); while (buffer.hasRemaining) channel.write(buffer); buffer.clear()
          }
          var i = 0
          while (i < width) {
            val v = inputs(k * width + i)
            buffer.putLong(if (v >= min(i) && v <= max(i)) v else encodeSlowly(inputPorts(i), BigInt(v), k))
            i += 1
          }
          k += 1
        }
        buffer.flip()
        while (buffer.hasRemaining) channel.write(buffer)
        count.toLong
      } finally channel.close()
    } { (out, accepted) =>
      var k = 0
      val results = readRecords(out, outRecord) { b =>
        b.getLong() // the cycle
        if (k >= count)
          throw new IllegalStateException(s"the RTL returned more than $count results for $count samples")
        var i = 0
        while (i < outWidth) { outputs(k * outWidth + i) = b.getLong(); i += 1 }
        k += 1
      }
      if (results != count)
        throw new IllegalStateException(s"the RTL returned $results results for $count samples")
      (results, readRecords(accepted, 8) { b => b.getLong(); () })
    }
  }

  /**
   * A stimulus run: `cycles` clocks after reset, each as `stimulus` says (records in increasing cycles, each
   * before `cycles`; clocks without one are quiet), drawing a sample from `samples` (values in the order of
   * `ports.inputs`) for every offer. What the design did goes to `onObserved` in clock order, so memory stays
   * constant however long the run. Host actions need a design with a host port (`ports.host`).
   */
  def drive(samples: Iterator[Seq[BigInt]], stimulus: Iterator[ClockStimulus], cycles: Long)(
      onObserved: Observed => Unit
  ): HarnessStats = {
    require(cycles >= 0, s"harness: cycles must be >= 0, got $cycles")
    val dir = Files.createTempDirectory("reducer-load-harness-run-")
    try {
      val (in, stim, observed) =
        (dir.resolve("inputs.bin"), dir.resolve("stimulus.bin"), dir.resolve("observed.bin"))
      val written = writeInputs(in, samples)
      val offers = writeStimulus(stim, stimulus, cycles)
      require(offers <= written, s"harness: the stimulus offers $offers samples, $written were given")
      val (log, seconds) =
        launch(Seq("--stimulus", in.toString, stim.toString, observed.toString, cycles.toString))
      readObserved(observed, onObserved)
      stats(log, seconds)
    } finally VerilatorHarness.deleteTree(dir)
  }

  /** Returns the number of offers. */
  private def writeStimulus(path: Path, stimulus: Iterator[ClockStimulus], cycles: Long): Long = {
    val channel = FileChannel.open(path, StandardOpenOption.CREATE_NEW, StandardOpenOption.WRITE)
    val address = ports.host.map(_.readAddress)
    try {
      val buffer = ByteBuffer.allocate(16 * 8192).order(ByteOrder.LITTLE_ENDIAN)
      var last = -1L
      var offers = 0L
      stimulus.foreach { c =>
        require(c.cycle > last && c.cycle < cycles, s"stimulus: cycle ${c.cycle} after $last, of $cycles")
        require(
          ports.host.nonEmpty || !c.hostAction,
          s"stimulus: cycle ${c.cycle}: the design has no host port"
        )
        c.read.foreach { a =>
          require(address.exists(_.maxValue >= a), s"stimulus: cycle ${c.cycle}: read address $a too wide")
        }
        if (buffer.remaining < 16) {
          buffer.flip(); while (buffer.hasRemaining) channel.write(buffer); buffer.clear()
        }
        buffer.putLong(c.cycle).putLong(c.word)
        last = c.cycle
        if (c.offer) offers += 1
      }
      buffer.flip()
      while (buffer.hasRemaining) channel.write(buffer)
      offers
    } finally channel.close()
  }

  /** The stimulus run's records, decoded in file order. */
  private def readObserved(path: Path, each: Observed => Unit): Unit = {
    val channel = FileChannel.open(path, StandardOpenOption.READ)
    try {
      val buffer = ByteBuffer.allocate(8 * 65536).order(ByteOrder.LITTLE_ENDIAN)
      buffer.limit(0)
      def word(): Long = {
        if (buffer.remaining < 8) {
          buffer.compact()
          while (buffer.position() < 8 && channel.read(buffer) >= 0) ()
          buffer.flip()
          if (buffer.remaining < 8) throw new IllegalStateException(s"$path ends inside a record")
        }
        buffer.getLong()
      }
      def more: Boolean = buffer.hasRemaining || {
        buffer.clear(); val n = channel.read(buffer); buffer.flip(); n > 0
      }
      while (more) {
        val cycle = word()
        word() match {
          case Observed.takenTag => each(Observed.Taken(cycle))
          case Observed.outputTag =>
            val values = new Array[BigInt](outputPorts.length)
            var i = 0
            while (i < values.length) { values(i) = decode(outputPorts(i), word()); i += 1 }
            each(Observed.Output(cycle, ArraySeq.unsafeWrapArray(values)))
          case Observed.doneTag => each(Observed.SnapshotDone(cycle))
          case Observed.readTag => each(Observed.ReadData(cycle, word()))
          case other            => throw new IllegalStateException(s"$path: unknown record tag $other")
        }
      }
    } finally channel.close()
  }

  /** Run the executable with `args`; its printed figures and wall seconds. */
  private def launch(args: Seq[String]): (String, Double) = {
    val log = new StringBuilder
    val start = System.nanoTime()
    val status = (executable.toString +: args).!(
      ProcessLogger(l => log.append(l).append('\n'), l => log.append(l).append('\n'))
    )
    val seconds = (System.nanoTime() - start) / 1e9
    if (status != 0)
      throw new IllegalStateException(s"harness $executable failed (exit $status): ${log.toString.trim}")
    (log.toString, seconds)
  }

  private def stats(log: String, seconds: Double): HarnessStats = {
    def printed(pattern: String, what: String) = pattern.r
      .findFirstMatchIn(log)
      .map(_.group(1))
      .getOrElse(throw new IllegalStateException(s"harness $executable printed no $what: ${log.trim}"))
    HarnessStats(
      printed("samples=(\\d+)", "sample count").toLong,
      printed("outputs=(\\d+)", "output count").toLong,
      printed("cycles=(\\d+)", "cycle count").toLong,
      seconds,
      printed("cpu_seconds=([0-9.]+)", "CPU time").toDouble
    )
  }

  /**
   * Write the inputs with `write` (returns the sample count), run the harness, read its files with `read`
   * (outputs, accepted).
   */
  private def runProcess(samplePeriod: Int, drainCycles: Int, maxStallCycles: Long)(
      write: Path => Long
  )(read: (Path, Path) => (Long, Long)): HarnessStats = {
    val dir = Files.createTempDirectory("reducer-load-harness-run-")
    try {
      val (in, out, accepted) =
        (dir.resolve("inputs.bin"), dir.resolve("outputs.bin"), dir.resolve("accepted.bin"))
      val written = write(in)
      val (log, seconds) = launch(
        Seq(
          in.toString,
          out.toString,
          accepted.toString,
          samplePeriod.toString,
          drainCycles.toString,
          maxStallCycles.toString
        )
      )
      val printed = stats(log, seconds)
      val (outputs, taken) = read(out, accepted)
      if (taken != written)
        throw new IllegalStateException(
          s"harness took $taken of $written samples (drain or stall limit reached?)"
        )
      printed.copy(samples = taken, outputs = outputs)
    } finally VerilatorHarness.deleteTree(dir)
  }

  /** [[stream]], collecting everything in memory. */
  def run(
      inputs: Iterable[Seq[BigInt]],
      samplePeriod: Int = 1,
      drainCycles: Int = 256,
      maxStallCycles: Long = 1000000L
  ): HarnessResult = {
    val outputs = ArrayBuffer.empty[IndexedSeq[BigInt]]
    val outputCycles = ArrayBuffer.empty[Long]
    val accepted = ArrayBuffer.empty[Long]
    val stats = stream(inputs.iterator, samplePeriod, drainCycles, maxStallCycles)(
      (cycle, values) => { outputCycles += cycle; outputs += values },
      cycle => accepted += cycle
    )
    HarnessResult(outputs.toIndexedSeq, ArraySeq.from(outputCycles), ArraySeq.from(accepted), stats)
  }

  /** Unsigned 64-bit values come back as negative longs: add 2^64 back. */
  private def decode(p: HarnessPort, raw: Long): BigInt =
    if (p.signed || raw >= 0) BigInt(raw) else BigInt(raw) + (BigInt(1) << 64)

  // Port limits as longs, for the common case of values that fit a long (the max of an unsigned
  // 64-bit port does not: such values take the BigInt comparison).
  private val inputMin = inputPorts.map(_.minValue.toLong)
  private val inputMax = inputPorts.map(p => if (p.maxValue.isValidLong) p.maxValue.toLong else Long.MaxValue)

  /** Two's complement of input `i`'s value `v` in 64 bits, after checking it fits the port. */
  private def encode(i: Int, v: BigInt, sample: Long): Long =
    if (v.isValidLong && v.toLong >= inputMin(i) && v.toLong <= inputMax(i)) v.toLong
    else encodeSlowly(inputPorts(i), v, sample)

  private def encodeSlowly(p: HarnessPort, v: BigInt, sample: Long): Long = {
    if (v < p.minValue || v > p.maxValue)
      throw new IllegalArgumentException(
        s"harness: sample $sample: ${p.name} = $v does not fit ${p.width} " +
          s"${if (p.signed) "signed" else "unsigned"} bits (${p.minValue} to ${p.maxValue})"
      )
    v.toLong // the low 64 bits: the raw pattern for unsigned 64-bit ports
  }

  private def writeInputs(path: Path, inputs: Iterator[Seq[BigInt]]): Long = {
    val channel = FileChannel.open(path, StandardOpenOption.CREATE_NEW, StandardOpenOption.WRITE)
    try {
      val buffer = ByteBuffer.allocate(inRecord * 8192).order(ByteOrder.LITTLE_ENDIAN)
      var count = 0L
      inputs.foreach { sample =>
        require(
          sample.size == ports.inputs.size,
          s"harness: sample $count has ${sample.size} values for ${ports.inputs.size} input ports"
        )
        if (buffer.remaining < inRecord) {
          buffer.flip(); while (buffer.hasRemaining) channel.write(buffer); buffer.clear()
        }
        val values = sample.iterator
        var i = 0
        while (i < inputPorts.length) { buffer.putLong(encode(i, values.next(), count)); i += 1 }
        count += 1
      }
      buffer.flip()
      while (buffer.hasRemaining) channel.write(buffer)
      count
    } finally channel.close()
  }

  /** Calls `each` with a buffer positioned at every record of `path`; returns the record count. */
  private def readRecords(path: Path, size: Int)(each: ByteBuffer => Unit): Long = {
    val channel = FileChannel.open(path, StandardOpenOption.READ)
    try {
      require(channel.size % size == 0, s"harness output $path is not a whole number of records")
      val buffer = ByteBuffer.allocate(size * 8192).order(ByteOrder.LITTLE_ENDIAN)
      var count = 0L
      while (channel.read(buffer) >= 0 || buffer.position() > 0) {
        buffer.flip()
        while (buffer.remaining >= size) { each(buffer); count += 1 }
        buffer.compact()
        if (buffer.position() > 0 && channel.position() == channel.size)
          throw new IllegalStateException(s"$path ends inside a record")
      }
      count
    } finally channel.close()
  }
}

/**
 * Every valid output of a harness run (values in the order of `HarnessPorts.outputs`) with the cycle it
 * appeared in, and the cycle each input sample was taken (valid && ready) in, counted from the first clock
 * after reset.
 */
final case class HarnessResult(
    outputs: IndexedSeq[IndexedSeq[BigInt]],
    outputCycles: IndexedSeq[Long],
    acceptedCycles: IndexedSeq[Long],
    stats: HarnessStats
)

/**
 * What one harness run did: samples taken, valid outputs, clock cycles after reset, the simulator process's
 * wall time (start-up and file I/O included) and its CPU time (what it takes on a core of its own; on a
 * shared machine the wall time also counts other work).
 */
final case class HarnessStats(
    samples: Long,
    outputs: Long,
    cycles: Long,
    seconds: Double,
    cpuSeconds: Double
) {
  def samplesPerSecond: Double = samples / seconds.max(1e-9)
  def cyclesPerCpuSecond: Double = cycles / cpuSeconds.max(1e-9)
}
