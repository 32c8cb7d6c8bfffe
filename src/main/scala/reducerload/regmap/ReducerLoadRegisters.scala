package reducerload.regmap

import reducerload.compiler.Compiled
import reducerload.config.Settings
import reducerload.fixedpoint.FixedFormat
import reducerload.monitor.{JointField, MonitorParams, MonitorSnapshot, RegisterEntry, RegisterKey}
import reducerload.robot.JointKind

import java.nio.charset.StandardCharsets
import java.security.MessageDigest

/** The format of one data port of the datapath, as the identification block reports it. */
final case class PortFormat(name: String, format: FieldFormat, meaning: String)

/** The generator's version (build.sbt's, through the generated resource), packed major.minor.patch. */
object GeneratorVersion {
  val text: String = {
    val in = getClass.getResourceAsStream("/reducerload/version.txt")
    require(in != null, "the build's reducerload/version.txt resource is missing (build.sbt generates it)")
    try new String(in.readAllBytes(), StandardCharsets.UTF_8).trim
    finally in.close()
  }

  /** major << 16 | minor << 8 | patch; a suffix after the patch number (-SNAPSHOT) is not encoded. */
  val packed: BigInt = {
    val parts = text.takeWhile(c => c.isDigit || c == '.').split('.').map(_.toInt).padTo(3, 0)
    require(parts.forall(p => p >= 0 && p <= 255), s"generator version $text: each part must be 0..255")
    BigInt((parts(0) << 16) | (parts(1) << 8) | parts(2))
  }
}

/**
 * The register map of a monitored arm behind a bus, described once: every emitter (C header, markdown,
 * SystemRDL) and the RTL decoder ([[AvalonCsr]]) read this description.
 *
 * Blocks, in address order: `id` (what design this is), `ctrl` (monitor snapshot and clear, status),
 * `counters` (sample counters), `irq` (the monitor's limit events), `payload` (reserved for the payload and
 * gravity registers and their commit, issue 31: [[payloadBlock]] is the one place to fill), `monitor` (the
 * monitor's shadow bank, word for word as [[reducerload.monitor.RegisterMap]] lays it out, so the decoder
 * passes the word offset straight to the monitor's read port).
 */
object ReducerLoadRegisters {
  val name = "reducer_load"

  /** "RLOD": the first word of every design's map, so a driver knows it reads this kind of core at all. */
  val magic: BigInt = BigInt(0x524c4f44L)

  /** Interrupt events: bit index and meaning, the same in the status and the mask. */
  sealed abstract class Event(val name: String, val bit: Int, val meaning: String)
  object Event {
    case object RepeatedPeak
        extends Event(
          "repeated_peak",
          0,
          "a joint's |tau| exceeded T_R for the first time since the monitor's clear"
        )
    case object MomentaryPeak
        extends Event(
          "momentary_peak",
          1,
          "a joint's |tau| exceeded T_M for the first time since the monitor's clear"
        )
    case object CounterSaturated
        extends Event(
          "counter_saturated",
          2,
          "a joint's histogram counter saturated for the first time since the clear"
        )
    val all: Seq[Event] = Seq(RepeatedPeak, MomentaryPeak, CounterSaturated)

    /** The monitor flag whose rise is the event ([[JointField.FlagBit]]). */
    def flagBit(e: Event): Int = e match {
      case RepeatedPeak     => JointField.FlagBit.repeatedPeakSeen
      case MomentaryPeak    => JointField.FlagBit.momentaryPeakSeen
      case CounterSaturated => JointField.FlagBit.histogramSaturated
    }
  }

  /** Control pulses: bit index and meaning. */
  sealed abstract class Command(val name: String, val bit: Int, val meaning: String)
  object Command {
    case object Snapshot
        extends Command(
          "snapshot",
          0,
          "copy every joint's live monitor state into the shadow bank (monitor block)"
        )
    case object Clear
        extends Command("clear", 1, "reset the live monitor state (with snapshot: read-and-reset)")
    case object ClearCounters extends Command("clear_counters", 2, "reset the counter block to 0")
    val all: Seq[Command] = Seq(Snapshot, Clear, ClearCounters)
  }

  /** Status bits: the last requested snapshot is in the shadow bank; a joint is in a momentary-peak event. */
  val snapshotReadyBit = 0
  val inEventBit = 1

  /** A design's identity for the id block: SHA-256 of the settings and the robot, first 4 bytes. */
  def designHash(c: Compiled): BigInt = {
    val chain = c.arm.chain.copy(warnings = Nil, source = "")
    // The robot's file path is where it lies, not what it is: the chain (from the file) stands for it.
    val settings = Settings.render(c.config.copy(robot = c.config.robot.copy(source = chain.name)), Nil)
    val digest =
      MessageDigest.getInstance("SHA-256").digest((settings + "\n" + chain).getBytes(StandardCharsets.UTF_8))
    BigInt(1, digest.take(4))
  }

  /** The datapath's ports' formats (every joint in one format per port kind, as the ports carry them). */
  def ports(c: Compiled): Seq[PortFormat] = {
    val n = c.arm.numerics
    Seq(
      PortFormat("q", FieldFormat.BinaryAngle(n.angleBits), "angle inputs: unsigned binary angle"),
      PortFormat("qd", FieldFormat.Fixed(n.velocityPortFormat, "rad/s"), "velocity inputs (m/s: prismatic)"),
      PortFormat("qdd", FieldFormat.Fixed(n.accelerationPortFormat, "rad/s^2"), "acceleration inputs"),
      PortFormat(
        "tau",
        FieldFormat.Fixed(c.arm.analysis.outputPortFormat, "N.m"),
        "torque outputs (N: prismatic)"
      )
    )
  }

  private def ro(name: String, lsb: Int, width: Int, meaning: String, reset: BigInt = 0) =
    Field(name, lsb, width, Access.ReadOnly, meaning, reset = reset)

  /** A format register: width, integer and fraction bits, signedness of a port's codes. */
  private def formatRegister(p: PortFormat): Register = {
    val (width, intBits, fracBits, signed) = p.format match {
      case FieldFormat.Fixed(f, _)       => (f.width, f.intBits, f.fracBits, 1)
      case FieldFormat.BinaryAngle(bits) => (bits, 0, bits, 0)
      case other => throw new IllegalArgumentException(s"port ${p.name}: $other is no code format")
    }
    Register(
      s"${p.name}_format",
      s"${p.meaning}: code x 2^-frac_bits ${unitOf(p.format)}",
      Seq(
        ro("frac_bits", 0, 8, "fraction bits", fracBits),
        Field(
          "int_bits",
          8,
          8,
          Access.ReadOnly,
          "integer bits (two's complement)",
          signed = true,
          reset = intBits & 0xff
        ),
        ro("width", 16, 8, "code width in bits", width),
        ro("is_signed", 24, 1, "1: two's complement code, 0: unsigned", signed)
      ),
      Source.Constant
    )
  }

  private def unitOf(f: FieldFormat): String = f match {
    case FieldFormat.BinaryAngle(_) => "turns (2 pi rad per turn)"
    case FieldFormat.Fixed(_, unit) => unit
    case _                          => ""
  }

  private def idBlock(c: Compiled, ports: Seq[PortFormat]): Block = Block(
    "id",
    "identification: a driver checks these before anything else",
    BlockContent.Registers(
      Seq(
        Register(
          "magic",
          "0x524C4F44 (\"RLOD\")",
          Seq(ro("value", 0, 32, "magic number", magic)),
          Source.Constant
        ),
        Register(
          "version",
          s"generator version ${GeneratorVersion.text}",
          Seq(
            ro("patch", 0, 8, "patch", GeneratorVersion.packed & 0xff),
            ro("minor", 8, 8, "minor", (GeneratorVersion.packed >> 8) & 0xff),
            ro("major", 16, 8, "major", GeneratorVersion.packed >> 16)
          ),
          Source.Constant
        ),
        Register(
          "design_hash",
          "SHA-256 of the effective settings and the robot's chain, first 4 bytes (big-endian)",
          Seq(ro("value", 0, 32, "hash", designHash(c))),
          Source.Constant
        ),
        Register(
          "shape",
          "joint count and sample spacing",
          Seq(
            ro("joints", 0, 8, "joints", c.arm.chain.size),
            ro("clocks_per_sample", 16, 16, "clocks between samples", c.arm.schedule.clocksPerSample)
          ),
          Source.Constant
        )
      ) ++ ports.map(formatRegister)
    )
  )

  private def ctrlBlock(m: MonitorParams) = Block(
    "ctrl",
    "monitor control and status",
    BlockContent.Registers(
      Seq(
        Register(
          "control",
          "command pulses",
          Command.all.map(k => Field(k.name, k.bit, 1, Access.WriteOneToPulse, k.meaning, FieldFormat.Flag)),
          Source.Control
        ),
        Register(
          "status",
          "monitor status",
          Seq(
            Field(
              "snapshot_ready",
              snapshotReadyBit,
              1,
              Access.ReadOnly,
              "1: the last requested snapshot is in the monitor block (0 from the request until it lands)",
              FieldFormat.Flag,
              reset = 1
            ),
            Field(
              "in_event",
              inEventBit,
              1,
              Access.ReadOnly,
              "1: some joint is in a momentary-peak event now (|tau| > T_M; live, not the snapshot)",
              FieldFormat.Flag,
              reset = if (m.clearInEvent) 1 else 0
            )
          ),
          Source.Status
        )
      )
    )
  )

  private val counterBlock = Block(
    "counters",
    "sample counters, modulo 2^32 (take differences); ctrl.control.clear_counters resets them",
    BlockContent.Registers(
      SampleCounter.all.map(k =>
        Register(k.name, k.meaning, Seq(ro("count", 0, 32, k.meaning)), Source.Counter(k))
      )
    )
  )

  private val irqBlock = {
    def fields(access: Access, what: String) =
      Event.all.map(e => Field(e.name, e.bit, 1, access, s"$what: ${e.meaning}", FieldFormat.Flag))
    Block(
      "irq",
      "interrupt: the line is high while (status & mask) != 0",
      BlockContent.Registers(
        Seq(
          Register(
            "status",
            "events seen (write 1 to clear)",
            fields(Access.WriteOneToClear, "seen"),
            Source.InterruptStatus
          ),
          Register(
            "mask",
            "1: the event raises the line",
            fields(Access.ReadWrite, "enable"),
            Source.InterruptMask
          )
        )
      )
    )
  }

  /**
   * The payload and gravity registers and their commit: issue 31 replaces this reservation with a
   * [[BlockContent.Registers]] block of the same name (64 words keep every later address).
   */
  val payloadBlock: Block = Block(
    "payload",
    "reserved: payload and gravity registers and their commit (run-time payload, issue 31); reads 0",
    BlockContent.Reserved(CsrMap.minSpan, "run-time payload inputs (issue 31)")
  )

  /** The SI format of a monitor figure of joint `j`, when it has one. */
  private def figureFormat(m: MonitorParams, c: Compiled, j: Int, f: JointField): FieldFormat = {
    val prismatic = c.arm.chain.joints(j).kind == JointKind.Prismatic
    val torque = FieldFormat.Fixed(m.torqueFormats(j), if (prismatic) "N" else "N.m")
    val speed = FieldFormat.Fixed(m.velocityFormats(j), if (prismatic) "m/s" else "rad/s")
    f match {
      case JointField.PeakTorque | JointField.MinTorque | JointField.LastEventPeak => torque
      case JointField.LastEventSpeed | JointField.SpeedSum                         => speed
      case _                                                                       => FieldFormat.Integer
    }
  }

  /** A monitor register's C name: `j<n>_<field>` (joint names need not be C identifiers, numbers are). */
  private def figureName(e: RegisterEntry): String = e.key match {
    case RegisterKey.Id            => "monitor_id"
    case RegisterKey.SnapshotCount => "snapshot_count"
    case RegisterKey.Joint(j, f)   => s"j${j + 1}_${f.name}"
  }

  /**
   * One 32-bit register per word of each monitor register, least significant word first (`_w0`, `_w1`). A
   * signed value fills its top word (sign-extended); the SI format is on word 0's field and scales the
   * assembled value. Reset values: the shadow bank after reset (the cleared state, as MonitorModel has it).
   */
  private def monitorBlock(m: MonitorParams, c: Compiled): Block = {
    val afterReset = MonitorSnapshot.cleared(m).bank(m)
    def field(
        name: String,
        lsb: Int,
        width: Int,
        meaning: String,
        word: Int,
        format: FieldFormat,
        signed: Boolean
    ) =
      Field(
        name,
        lsb,
        width,
        Access.ReadOnly,
        meaning,
        format,
        signed,
        (afterReset(word) >> lsb) & ((BigInt(1) << width) - 1)
      )
    Block(
      "monitor",
      "the monitor's shadow bank: what the last snapshot saw (docs/monitor.md)",
      BlockContent.Registers(m.registerMap.entries.flatMap { e =>
        val base = figureName(e)
        val format = e.key match {
          case RegisterKey.Joint(j, f) => figureFormat(m, c, j, f)
          case _                       => FieldFormat.Integer
        }
        (0 until e.words).map { w =>
          val word = e.address + w
          val name = if (e.words == 1) base else s"${base}_w$w"
          val last = w == e.words - 1
          val width = if (!last || e.signed) 32 else e.width - 32 * w
          val meaning = (if (e.words == 1) "" else s"bits ${32 * w}.. of ${e.width}: ") + e.meaning
          val fields = e.key match {
            case RegisterKey.Joint(_, JointField.Flags) =>
              Seq(
                "repeated_peak_seen" -> JointField.FlagBit.repeatedPeakSeen,
                "momentary_peak_seen" -> JointField.FlagBit.momentaryPeakSeen,
                "in_event" -> JointField.FlagBit.inEvent,
                "histogram_saturated" -> JointField.FlagBit.histogramSaturated
              ).map { case (n, bit) =>
                field(n, bit, 1, n.replace('_', ' '), word, FieldFormat.Flag, signed = false)
              }
            case _ =>
              Seq(
                field(
                  "value",
                  0,
                  width,
                  e.meaning,
                  word,
                  if (w == 0) format else FieldFormat.Integer,
                  e.signed && last
                )
              )
          }
          Register(name, meaning, fields, Source.Monitor(e, w))
        }
      })
    )
  }

  /** The map of a compiled design with a monitor. */
  def apply(c: Compiled): CsrMap = {
    val m = c.monitor.getOrElse(
      throw new IllegalArgumentException("the register map needs the monitor (monitor.enabled = true)")
    )
    val ps = ports(c)
    CsrMap
      .place(
        name,
        s"${c.arm.chain.name}: ${c.arm.chain.size} joints, ${c.arm.tag}",
        Seq(idBlock(c, ps), ctrlBlock(m), counterBlock, irqBlock, payloadBlock, monitorBlock(m, c))
      )
      .copy(ports = ps)
  }
}
