package reducerload.regmap

import reducerload.arm.ArmOutputCodes
import reducerload.graph.SampleCodes

import java.io.{BufferedReader, InputStreamReader, OutputStreamWriter}
import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path, Paths}
import scala.collection.mutable.ArrayBuffer
import scala.sys.process._

/** What a C program served by [[BusFunctionalModel]] did: exit status, its result lines, its transactions. */
final case class BfmRun(exit: Int, results: Map[String, String], reads: Int, writes: Int, errors: String) {

  /** A result the program printed as `key value`. */
  def apply(key: String): String =
    results.getOrElse(
      key,
      throw new NoSuchElementException(s"the C program printed no '$key'; errors: $errors")
    )
}

/**
 * The bus of a C program as the simulated RTL's: each request line the program writes (`R <byte offset>`, `W
 * <byte offset> <value>`, hexadecimal) becomes `read(word)` or `write(word, data)`, a read's value goes back
 * on its standard input; every other line is a result `key value`. The functions are the only link to the
 * simulator, so the same model serves any DUT with a word-addressed register bus ([[CsrBus]] on the
 * `reducer_load` wrapper, [[RegisterFileModel]], or another word-addressed slave).
 */
final class BusFunctionalModel(read: Int => BigInt, write: (Int, BigInt) => Unit) {
  private def word(hexOffset: String): Int = {
    val offset = Integer.parseUnsignedInt(hexOffset, 16)
    require(offset % 4 == 0, s"the C program addressed byte 0x$hexOffset: registers are 32-bit words")
    offset / 4
  }

  /** Run `command` to its end, serving its bus requests in order. */
  def serve(command: Seq[String]): BfmRun = {
    val process = new java.lang.ProcessBuilder(command: _*).start()
    val errors = new StringBuilder
    val errorReader = new Thread(() =>
      scala.io.Source.fromInputStream(process.getErrorStream, "UTF-8").getLines().foreach { l =>
        errors.synchronized(errors.append(l).append('\n'))
      }
    )
    errorReader.start()
    val in = new BufferedReader(new InputStreamReader(process.getInputStream, StandardCharsets.UTF_8))
    val out = new OutputStreamWriter(process.getOutputStream, StandardCharsets.UTF_8)
    val results = ArrayBuffer.empty[(String, String)]
    var (reads, writes) = (0, 0)
    try
      Iterator.continually(in.readLine()).takeWhile(_ != null).foreach { line =>
        line.split(' ') match {
          case Array("R", offset) =>
            out.write(read(word(offset)).toString(16) + "\n")
            out.flush()
            reads += 1
          case Array("W", offset, value) =>
            write(word(offset), BigInt(value, 16))
            writes += 1
          case Array(key, value) => results += key -> value
          case _                 => results += line -> ""
        }
      }
    finally out.close()
    val exit = process.waitFor()
    errorReader.join()
    BfmRun(exit, results.toMap, reads, writes, errors.synchronized(errors.toString))
  }
}

/**
 * The register map's software view without RTL: RW fields hold what is written, constants read their value,
 * W1S fields read 0, a payload commit counts the sequence up and latches the staged parameters, and a sample
 * start computes the sample mode's result with `evaluate` (the bit-accurate model) from the registers' codes
 * and the committed parameters. For driver checks that need no hardware timing.
 */
final class RegisterFileModel(
    map: CsrMap,
    evaluate: Option[(SampleCodes, IndexedSeq[BigInt]) => ArmOutputCodes] = None
) {
  private val byWord = map.registers.map(r => r.word -> r).toMap
  private val values =
    scala.collection.mutable.Map.empty[Int, BigInt] ++ map.registers.map(r => r.word -> r.register.reset)
  private def bySource(p: Source => Boolean): Seq[PlacedRegister] =
    map.registers.filter(r => p(r.register.source))
  private def code(r: PlacedRegister): BigInt = {
    val f = r.register.fields.head
    val raw = (values(r.word) & f.mask) >> f.lsb
    if (f.signed) reducerload.fixedpoint.FixedFormat.fromTwosComplement(raw, f.width) else raw
  }
  private var committed: IndexedSeq[BigInt] =
    bySource { case Source.Parameter(_, 0) => true; case _ => false }.map(r => code(r)).toIndexedSeq

  def read(word: Int): BigInt = byWord.get(word).fold(BigInt(0)) { r =>
    r.register.fields.filter(_.access != Access.WriteOneToPulse).map(f => values(word) & f.mask).sum
  }

  def write(word: Int, data: BigInt): Unit = byWord.get(word).foreach { r =>
    val rw = r.register.fields.filter(_.access == Access.ReadWrite).map(_.mask).sum
    values(word) = (values(word) & ~rw) | (data & rw)
    if ((data & 1) == 1) r.register.source match {
      case Source.PayloadCommit =>
        val seq = bySource(_ == Source.PayloadSequence).head.word
        values(seq) = (values(seq) + 1) & 0xff
        committed = bySource { case Source.Parameter(_, 0) => true; case _ => false }.map(code).toIndexedSeq
      case Source.SampleStart => evaluate.foreach(start)
      case _                  => ()
    }
  }

  /** `evaluate` gets the sample's codes and the committed parameters' codes (`numerics.parameters` order). */
  private def start(evaluate: (SampleCodes, IndexedSeq[BigInt]) => ArmOutputCodes): Unit = {
    def inputs(kind: SampleKind) =
      bySource { case Source.SampleInput(`kind`, _, 0) => true; case _ => false }.map(code).toIndexedSeq
    val out = evaluate(
      SampleCodes(inputs(SampleKind.Angle), inputs(SampleKind.Velocity), inputs(SampleKind.Acceleration)),
      committed
    )
    // Wide codes: word w holds bits 32 w.. of the two's complement code (the top word sign-extended).
    map.registers.foreach { r =>
      r.register.source match {
        case Source.SampleTorque(j, w) =>
          values(r.word) = (out.tau(j) >> (32 * w)) & r.register.fields.head.mask
        case _ => ()
      }
    }
    bySource(_ == Source.SampleFlags).foreach { r =>
      values(r.word) = out.outOfRange.zipWithIndex.map { case (f, j) =>
        if (f) BigInt(1) << j else BigInt(0)
      }.sum
    }
    bySource(_ == Source.SampleStatus).foreach(r =>
      values(r.word) = BigInt(1) << ReducerLoadRegisters.sampleDoneBit
    )
  }

  /** The committed parameters' codes, in `numerics.parameters` order. */
  def committedCodes: IndexedSeq[BigInt] = committed
}

/** The C driver (driver/ at the repository's top) built with a design's headers, and its test program. */
object CDriver {
  val flags: Seq[String] = Seq("-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic")

  def sources: Path = Paths.get(sys.env.getOrElse("REDUCERLOAD_CWD", ".")).resolve("driver")

  /** The design's generated headers, written into `dir`. */
  def writeHeaders(dir: Path, c: reducerload.compiler.Compiled, command: String): Unit = {
    val map = ReducerLoadRegisters(c)
    Files.write(dir.resolve(s"${map.name}_regs.h"), CHeader(map, command).getBytes(StandardCharsets.UTF_8))
    Files.write(
      dir.resolve(s"${map.name}_layout.h"),
      DriverLayout(c, command).getBytes(StandardCharsets.UTF_8)
    )
  }

  /** Write a test design's headers into the directory given (to build the driver by hand): planar3 or ur5. */
  def main(args: Array[String]): Unit = writeHeaders(
    Paths.get(args(0)),
    if (args.lift(1).contains("ur5")) ReducerLoadTopDesigns.ur5Payloaded else RegMapDesign.compiled,
    "CDriver.main"
  )

  /**
   * Write the design's generated headers into `dir` and compile the driver with the BFM test program there.
   */
  def buildTestProgram(dir: Path, c: reducerload.compiler.Compiled, command: String): Path = {
    writeHeaders(dir, c, command)
    val exe = dir.resolve("rl_bfm_main")
    val log = new StringBuilder
    val cmd = Seq("gcc") ++ flags ++ Seq("-I", dir.toString, "-I", sources.toString, "-o", exe.toString) ++
      Seq(sources.resolve("reducer_load.c").toString, sources.resolve("test/rl_bfm_main.c").toString)
    val status = cmd.!(ProcessLogger(l => log.append(l).append('\n'), l => log.append(l).append('\n')))
    require(status == 0, s"${cmd.mkString(" ")} failed:\n$log")
    exe
  }
}
