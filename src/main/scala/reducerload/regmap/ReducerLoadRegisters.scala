package reducerload.regmap

import reducerload.arm.{PayloadColumns, PayloadedArm}
import reducerload.compiler.Compiled
import reducerload.config.Settings
import reducerload.fixedpoint.FixedFormat
import reducerload.graph.{InertialParameter, Signal}
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
 * The register map of an arm behind a bus, described once: every emitter (C header, markdown, SystemRDL) and
 * the RTL decoder ([[ReducerLoadCore]]) read this description.
 *
 * Blocks, in address order: `id` (what design this is), `ctrl` (commands, monitor status), `counters` (sample
 * counters), `irq` (the monitor's limit events), `payload` (the run-time payload and gravity registers and
 * their commit; reserved without them), `sample` (the register-driven sample mode), `monitor` (the monitor's
 * shadow bank, word for word as [[reducerload.monitor.RegisterMap]] lays it out, so the decoder passes the
 * word offset straight to the monitor's read port).
 *
 * One rule for a design without the monitor: what needs the monitor is left out (the snapshot and clear
 * commands, the status register, the monitor block) and the irq block is reserved (reads 0; the line stays
 * low), so every other address is the same with and without the monitor.
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
    // The robot's file path is where it lies, not what it is: the chain (from the file) stands for it. The
    // values only: a reworded help text is the same design.
    val settings = Settings.values(c.config.copy(robot = c.config.robot.copy(source = chain.name)))
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
    ) ++ Option
      .when(n.parameters.nonEmpty)(
        PortFormat(
          "parameter",
          FieldFormat.Fixed(n.parameterPortFormat, "SI"),
          "run-time payload and gravity parameters (kg, m, kg.m^2, m/s^2)"
        )
      )
      .toSeq
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

  /** Commands a design has: all with the monitor, only the counters' clear without. */
  def commands(monitor: Boolean): Seq[Command] =
    if (monitor) Command.all else Seq(Command.ClearCounters)

  private def ctrlBlock(monitor: Option[MonitorParams]) = Block(
    "ctrl",
    if (monitor.isDefined) "commands, monitor status" else "commands",
    BlockContent.Registers(
      Register(
        "control",
        "command pulses",
        commands(monitor.isDefined).map(k =>
          Field(k.name, k.bit, 1, Access.WriteOneToPulse, k.meaning, FieldFormat.Flag)
        ),
        Source.Control
      ) +: monitor.toSeq.map(m =>
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

  private def irqBlock(monitor: Boolean): Block = {
    def fields(access: Access, what: String) =
      Event.all.map(e => Field(e.name, e.bit, 1, access, s"$what: ${e.meaning}", FieldFormat.Flag))
    if (!monitor)
      Block(
        "irq",
        "reserved: interrupt (the monitor's limit events; no monitor in this design); reads 0, the line stays low",
        BlockContent.Reserved(2, "the monitor's interrupt status and mask (monitor.enabled)")
      )
    else
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
   * A run-time parameter's register name: the payload's from its trajectory column, the gravity's by axis.
   */
  def parameterName(c: Compiled, s: Signal.Parameter): String = s match {
    case Signal.Inertial(j, par) if j == c.arm.chain.size - 1 =>
      PayloadColumns.names(InertialParameter.all.indexOf(par))
    case Signal.Inertial(j, par) => s"j${j + 1}_${par.symbol}"
    case Signal.Gravity(axis)    => "gravity_" + "xyz" (axis)
  }

  private def parameterUnit(s: Signal.Parameter): String = s match {
    case Signal.Inertial(_, InertialParameter.Mass)          => "kg"
    case Signal.Inertial(_, InertialParameter.Com(_))        => "m"
    case Signal.Inertial(_, InertialParameter.Inertia(_, _)) => "kg.m^2"
    case Signal.Gravity(_)                                   => "m/s^2"
  }

  /** 32-bit words a `width`-bit code takes. */
  def wordsOf(width: Int): Int = (width + CsrMap.dataBits - 1) / CsrMap.dataBits

  /**
   * The field of word `w` of a `width`-bit code, as the map's rule lays wide values out: 32-bit words, least
   * significant first, a signed code sign-extended to whole words (its top word's field signed, 32 bits); the
   * SI format on word 0's field (it scales the assembled value). `reset`: the code's value (negative for a
   * negative signed code).
   */
  private def wordField(
      width: Int,
      w: Int,
      access: Access,
      meaning: String,
      format: FieldFormat,
      signed: Boolean,
      reset: BigInt
  ): Field = {
    val words = wordsOf(width)
    val last = w == words - 1
    val bits =
      if (words == 1) width else if (!last || signed) CsrMap.dataBits else width - CsrMap.dataBits * w
    val all = reset & ((BigInt(1) << (CsrMap.dataBits * words)) - 1)
    Field(
      "value",
      0,
      bits,
      access,
      (if (words == 1) "" else s"bits ${CsrMap.dataBits * w}.. of $width: ") + meaning,
      if (w == 0) format else FieldFormat.Integer,
      signed && last,
      (all >> (CsrMap.dataBits * w)) & ((BigInt(1) << bits) - 1)
    )
  }

  /** A register name with its word suffix when the code takes more than one word. */
  private def wordName(name: String, width: Int, w: Int): String =
    if (wordsOf(width) == 1) name else s"${name}_w$w"

  /**
   * The payload and gravity registers and their commit: one RW register per run-time parameter in
   * `numerics.parameters`' order (a read returns the staged value; a code wider than 32 bits takes
   * consecutive words), a commit pulse and the committed sequence number. Without run-time parameters the 64
   * words stay reserved, so later addresses keep.
   */
  def payloadBlock(c: Compiled): Block = {
    val n = c.arm.numerics
    if (n.parameters.isEmpty)
      Block(
        "payload",
        "reserved: payload and gravity registers (payload.enabled, gravity.runtime); reads 0",
        BlockContent.Reserved(CsrMap.minSpan, "run-time payload and gravity registers")
      )
    else {
      val port = n.parameterPortFormat
      val resets = PayloadedArm.resetCodes(c.arm)
      val parameters = n.parameters.zipWithIndex.flatMap { case (s, k) =>
        val name = parameterName(c, s)
        (0 until wordsOf(port.width)).map { w =>
          Register(
            wordName(name, port.width, w),
            s"staged $name (declared ${n.parameterRanges(s)}); takes effect at the next commit",
            Seq(
              wordField(
                port.width,
                w,
                Access.ReadWrite,
                s"$name, ${parameterUnit(s)}",
                FieldFormat.Fixed(port, parameterUnit(s)),
                signed = true,
                resets(k)
              )
            ),
            Source.Parameter(k, w)
          )
        }
      }
      Block(
        "payload",
        "run-time payload and gravity: write the staged values, then commit; every sample taken after the " +
          "commit is computed with them (clamped and flagged beyond their declared ranges)",
        BlockContent.Registers(
          parameters ++ Seq(
            Register(
              "commit",
              "commit the staged values at the next sample boundary",
              Seq(
                Field(
                  "commit",
                  0,
                  1,
                  Access.WriteOneToPulse,
                  "make the staged values the ones samples are computed with; counts the sequence up",
                  FieldFormat.Flag
                )
              ),
              Source.PayloadCommit
            ),
            Register(
              "sequence",
              "the committed payload's sequence number (0 after reset: no payload, the elaboration gravity)",
              Seq(ro("value", 0, PayloadedArm.sequenceBits, "commits modulo 2^8")),
              Source.PayloadSequence
            )
          )
        )
      )
    }
  }

  /** Sample status bits. */
  val sampleBusyBit = 0
  val sampleDoneBit = 1

  private def jointUnit(c: Compiled, j: Int, revolute: String, prismatic: String): String =
    if (c.arm.chain.joints(j).kind == JointKind.Prismatic) prismatic else revolute

  /**
   * One register per joint and word of a per-joint code: the joints of one word at consecutive words (word 0
   * of every joint, then word 1 of every joint), so a driver indexes by joint with a stride of 4 bytes.
   */
  private def perJoint(c: Compiled, kind: String, width: Int)(
      register: (String, Int, Int) => Register
  ): Seq[Register] =
    for (w <- 0 until wordsOf(width); j <- 0 until c.arm.chain.size)
      yield register(wordName(s"${kind}_j${j + 1}", width, w), j, w)

  /**
   * The register-driven sample mode, for a host with no streaming path: write a sample's q, qd and qdd, pulse
   * `start`, wait for `status.done`, read the torques, the flags and the payload sequence. Per-joint codes as
   * [[perJoint]] lays them out. The sample goes through the datapath between stream samples (the stream
   * waits; the monitor sees it too).
   */
  def sampleBlock(c: Compiled): Block = {
    val n = c.arm.numerics
    val joints = c.arm.chain.size
    val payload = n.parameters.nonEmpty
    def inputs(kind: SampleKind): Seq[Register] = {
      def format(j: Int): FieldFormat = kind match {
        case SampleKind.Angle => FieldFormat.BinaryAngle(n.angleBits)
        case SampleKind.Velocity =>
          FieldFormat.Fixed(n.velocityPortFormat, jointUnit(c, j, "rad/s", "m/s"))
        case SampleKind.Acceleration =>
          FieldFormat.Fixed(n.accelerationPortFormat, jointUnit(c, j, "rad/s^2", "m/s^2"))
      }
      val width = format(0) match {
        case FieldFormat.Fixed(f, _)       => f.width
        case FieldFormat.BinaryAngle(bits) => bits
        case _                             => CsrMap.dataBits
      }
      val signed = kind != SampleKind.Angle
      perJoint(c, kind.name, width) { (name, j, w) =>
        Register(
          name,
          s"joint ${j + 1}'s ${kind.meaning}",
          Seq(wordField(width, w, Access.ReadWrite, kind.meaning, format(j), signed, 0)),
          Source.SampleInput(kind, j, w)
        )
      }
    }
    val tauFormat = c.arm.analysis.outputPortFormat
    // One register per computed torque (a closed form computes one joint's), named by its joint.
    val torqueJoints = StreamLayout.torqueJoints(c.arm)
    val tau =
      for (w <- 0 until wordsOf(tauFormat.width); (j, k) <- torqueJoints.zipWithIndex)
        yield Register(
          wordName(s"tau_j${j + 1}", tauFormat.width, w),
          s"joint ${j + 1}'s torque of the last sample",
          Seq(
            wordField(
              tauFormat.width,
              w,
              Access.ReadOnly,
              "torque",
              FieldFormat.Fixed(tauFormat, jointUnit(c, j, "N.m", "N")),
              signed = true,
              0
            )
          ),
          Source.SampleTorque(k, w)
        )
    Block(
      "sample",
      "register-driven sample mode: write q, qd, qdd; start; when done, read tau, flags" +
        (if (payload) " and the payload sequence" else "") +
        "; per-joint codes wider than 32 bits: word 0 of every joint, then word 1 of every joint",
      BlockContent.Registers(
        SampleKind.all.flatMap(inputs) ++ Seq(
          Register(
            "start",
            "start one sample",
            Seq(
              Field(
                "start",
                0,
                1,
                Access.WriteOneToPulse,
                "compute the sample in the q, qd, qdd registers (ignored while busy)",
                FieldFormat.Flag
              )
            ),
            Source.SampleStart
          ),
          Register(
            "status",
            "sample mode status",
            Seq(
              Field(
                "busy",
                sampleBusyBit,
                1,
                Access.ReadOnly,
                "1: from start until the result is in",
                FieldFormat.Flag
              ),
              Field(
                "done",
                sampleDoneBit,
                1,
                Access.ReadOnly,
                "1: the result registers hold the last started sample's (0 from start until then)",
                FieldFormat.Flag
              )
            ),
            Source.SampleStatus
          )
        ) ++ tau ++ Seq(
          Register(
            "flags",
            "the last sample's out-of-range flags: bit j-1 for joint j (its qd or qdd was clamped)",
            (0 until joints).map(j =>
              Field(s"j${j + 1}", j, 1, Access.ReadOnly, s"joint ${j + 1} out of range", FieldFormat.Flag)
            ),
            Source.SampleFlags
          )
        ) ++ Option
          .when(payload)(
            Register(
              "sequence",
              "the payload sequence number the last sample was computed with",
              Seq(ro("value", 0, PayloadedArm.sequenceBits, "payload sequence")),
              Source.SampleSequence
            )
          )
          .toSeq
      )
    )
  }

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

  /** The map of a compiled design, with or without the monitor. */
  def apply(c: Compiled): CsrMap = {
    val ps = ports(c)
    CsrMap
      .place(
        name,
        s"${c.arm.chain.name}: ${c.arm.chain.size} joints, ${c.arm.tag}",
        Seq(
          idBlock(c, ps),
          ctrlBlock(c.monitor),
          counterBlock,
          irqBlock(c.monitor.isDefined),
          payloadBlock(c),
          sampleBlock(c)
        ) ++ c.monitor.map(monitorBlock(_, c))
      )
      .copy(ports = ps, joints = Some(c.arm.chain.size))
  }
}
