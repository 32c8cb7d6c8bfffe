package reducerload.regmap

import reducerload.fixedpoint.FixedFormat
import reducerload.monitor.RegisterEntry

/** What software may do with a field, as SystemRDL and the C header name it. */
sealed abstract class Access(val name: String, val meaning: String)
object Access {
  case object ReadOnly extends Access("RO", "read only; writes are ignored")
  case object ReadWrite extends Access("RW", "read and write")
  case object WriteOneToClear extends Access("W1C", "read; writing 1 clears the bit, 0 leaves it")
  case object WriteOneToPulse
      extends Access("W1S", "write 1: a one-clock pulse to the hardware; writing 0 does nothing; reads 0")
  val all: Seq[Access] = Seq(ReadOnly, ReadWrite, WriteOneToClear, WriteOneToPulse)
}

/** How a field's code becomes a value: the C header's conversion constants come from here. */
sealed trait FieldFormat
object FieldFormat {

  /** An integer count or identifier: no unit. */
  case object Integer extends FieldFormat

  /** One bit. */
  case object Flag extends FieldFormat

  /** A fixed-point code: SI value = code x 2^-fracBits (the field may be wider: sign or zero extension). */
  final case class Fixed(format: FixedFormat, unit: String) extends FieldFormat

  /** A binary angle: rad = code x 2 pi / 2^bits (the datapath's angle inputs). */
  final case class BinaryAngle(bits: Int) extends FieldFormat

  /** The SI value of one code step, and its unit, when the format has one. */
  def scale(f: FieldFormat): Option[(Double, String)] = f match {
    case Fixed(format, unit) => Some((format.lsb, unit))
    case BinaryAngle(bits)   => Some((2 * math.Pi / math.pow(2.0, bits), "rad"))
    case Integer | Flag      => None
  }
}

/**
 * Bits `lsb` to `lsb + width - 1` of a 32-bit register. `reset` is the value after reset (a constant
 * register's value); `signed` fields are two's complement, sign-extended to the field's width.
 */
final case class Field(
    name: String,
    lsb: Int,
    width: Int,
    access: Access,
    meaning: String,
    format: FieldFormat = FieldFormat.Integer,
    signed: Boolean = false,
    reset: BigInt = 0
) {
  require(CsrMap.identifier.matches(name), s"field '$name' is not a C identifier in lower case")
  require(
    lsb >= 0 && width >= 1 && lsb + width <= CsrMap.dataBits,
    s"field $name: bits [$msb:$lsb] beyond 32"
  )
  require(
    reset >= 0 && reset.bitLength <= width,
    s"field $name: reset $reset does not fit $width bits (give negative values as their two's complement)"
  )
  def msb: Int = lsb + width - 1
  def mask: BigInt = ((BigInt(1) << width) - 1) << lsb
}

/** Where a register's value comes from in the hardware (the RTL decoder's only input besides the layout). */
sealed trait Source
object Source {

  /** The fields' reset values, fixed at generation. */
  case object Constant extends Source

  /** Command pulses (snapshot, clear, counter clear). */
  case object Control extends Source

  /** Status bits of the monitor. */
  case object Status extends Source

  /** A free-running sample counter. */
  final case class Counter(counter: SampleCounter) extends Source

  /** Interrupt status (W1C) and mask (RW). */
  case object InterruptStatus extends Source
  case object InterruptMask extends Source

  /** Word `word` (0 = least significant) of a monitor register ([[reducerload.monitor.RegisterMap]]). */
  final case class Monitor(entry: RegisterEntry, word: Int) extends Source

  /**
   * Word `word` of the staged value of run-time parameter `index` (`numerics.parameters`' order): written and
   * read back.
   */
  final case class Parameter(index: Int, word: Int) extends Source

  /** The payload commit pulse, and the committed payload's sequence number. */
  case object PayloadCommit extends Source
  case object PayloadSequence extends Source

  /**
   * The register-driven sample mode: word `word` of joint `joint`'s input of one kind, written and read back.
   */
  final case class SampleInput(kind: SampleKind, joint: Int, word: Int) extends Source

  /**
   * The sample mode's start pulse, its busy/done status, and its result: torques, flags, payload sequence.
   */
  case object SampleStart extends Source
  case object SampleStatus extends Source
  final case class SampleTorque(joint: Int, word: Int) extends Source
  case object SampleFlags extends Source
  case object SampleSequence extends Source
}

/** The joint inputs of one sample, in the order of the sample block and of the input stream's bit layout. */
sealed abstract class SampleKind(val name: String, val meaning: String)
object SampleKind {
  case object Angle extends SampleKind("q", "joint angle")
  case object Velocity extends SampleKind("qd", "joint velocity")
  case object Acceleration extends SampleKind("qdd", "joint acceleration")
  val all: Seq[SampleKind] = Seq(Angle, Velocity, Acceleration)
}

/** The counters of the counter block, in address order. */
sealed abstract class SampleCounter(val name: String, val meaning: String)
object SampleCounter {
  case object SamplesIn extends SampleCounter("samples_in", "samples taken on the input (valid and ready)")
  case object SamplesOut extends SampleCounter("samples_out", "samples given on the output (valid)")
  case object OutOfRange
      extends SampleCounter("out_of_range", "output samples with any joint's out-of-range flag set")
  case object Stalls
      extends SampleCounter(
        "stalls",
        "clocks with a sample offered on the input and not taken (valid, not ready)"
      )
  val all: Seq[SampleCounter] = Seq(SamplesIn, SamplesOut, OutOfRange, Stalls)
}

/** One 32-bit register: its fields (no two overlap) and where its value comes from. */
final case class Register(name: String, meaning: String, fields: Seq[Field], source: Source) {
  require(CsrMap.identifier.matches(name), s"register '$name' is not a C identifier in lower case")
  require(fields.nonEmpty, s"register $name has no field")
  fields.combinations(2).foreach { case Seq(a, b) =>
    require((a.mask & b.mask) == 0, s"register $name: fields ${a.name} and ${b.name} overlap")
  }
  require(fields.map(_.name).distinct.size == fields.size, s"register $name: a field name repeats")

  /** The value after reset (a constant register's value). */
  def reset: BigInt = fields.map(f => f.reset << f.lsb).sum
}

/** What a block holds: registers one word after the other, or a documented reserved span. */
sealed trait BlockContent
object BlockContent {
  final case class Registers(registers: Seq[Register]) extends BlockContent

  /** `words` reserved words: read 0, writes ignored, until `reason` fills them. */
  final case class Reserved(words: Int, reason: String) extends BlockContent
}

final case class Block(name: String, meaning: String, content: BlockContent) {
  require(CsrMap.identifier.matches(name), s"block '$name' is not a C identifier in lower case")
  def registers: Seq[Register] = content match {
    case BlockContent.Registers(rs)  => rs
    case BlockContent.Reserved(_, _) => Nil
  }
  def words: Int = content match {
    case BlockContent.Registers(rs)  => rs.size
    case BlockContent.Reserved(w, _) => w
  }

  /**
   * The block's address span in words: its size rounded up to a power of two, at least [[CsrMap.minSpan]]. A
   * block starts at a multiple of its span, so the decoder selects it by the top address bits alone.
   */
  def span: Int = Integer.highestOneBit((words.max(1) - 1).max(1)) * 2 max CsrMap.minSpan
}

/** A block at its word address. */
final case class PlacedBlock(block: Block, base: Int) {
  def registers: Seq[PlacedRegister] =
    block.registers.zipWithIndex.map { case (r, i) => PlacedRegister(this, r, base + i) }
}

/** A register at its word address; `cName` prefixes it with its block, unique in the map. */
final case class PlacedRegister(block: PlacedBlock, register: Register, word: Int) {
  def byteOffset: Int = 4 * word
  def cName: String = s"${block.block.name}_${register.name}"
}

/**
 * A register map described once: blocks in order, each at the lowest multiple of its span at or after the
 * previous block's end (one rule, [[CsrMap.place]]). 32-bit data bus, word addresses on the bus (Avalon-MM
 * slaves address words), byte offsets in the C header and SystemRDL. A value wider than 32 bits takes
 * consecutive registers, least significant word at the lowest address. `ports` are the formats of the
 * design's data ports, which the identification block reports and the C header converts; `joints`, when
 * given, the joint count the C header states (a driver indexes per-joint registers by it).
 */
final case class CsrMap(
    name: String,
    meaning: String,
    blocks: Seq[PlacedBlock],
    ports: Seq[PortFormat] = Nil,
    joints: Option[Int] = None
) {
  require(CsrMap.identifier.matches(name), s"register map '$name' is not a C identifier in lower case")
  val registers: Seq[PlacedRegister] = blocks.flatMap(_.registers)
  require(
    registers.map(_.cName).distinct.size == registers.size,
    s"register map $name: a register name repeats"
  )

  /** Words the decoder spans (a power of two: the end of the last block's span). */
  val words: Int = {
    val end = blocks.map(b => b.base + b.block.span).maxOption.getOrElse(CsrMap.minSpan)
    Integer.highestOneBit((end - 1).max(1)) * 2
  }
  val addressBits: Int = Integer.numberOfTrailingZeros(words)

  def block(name: String): PlacedBlock =
    blocks.find(_.block.name == name).getOrElse(throw new NoSuchElementException(s"no block $name"))
  def register(cName: String): PlacedRegister =
    registers.find(_.cName == cName).getOrElse(throw new NoSuchElementException(s"no register $cName"))
}

object CsrMap {
  val dataBits = 32

  /** The smallest block span, in words (0x100 bytes): small blocks keep their addresses as the map grows. */
  val minSpan = 64

  val identifier = "[a-z][a-z0-9_]*".r

  /** Blocks at their addresses: each at the first multiple of its span at or after the previous one's end. */
  def place(name: String, meaning: String, blocks: Seq[Block]): CsrMap = {
    val placed = blocks.foldLeft(Vector.empty[PlacedBlock]) { (done, b) =>
      val end = done.lastOption.fold(0)(p => p.base + p.block.span)
      val base = (end + b.span - 1) / b.span * b.span
      done :+ PlacedBlock(b, base)
    }
    CsrMap(name, meaning, placed)
  }
}
