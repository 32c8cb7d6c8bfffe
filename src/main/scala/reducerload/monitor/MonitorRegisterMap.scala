package reducerload.monitor

import reducerload.fixedpoint.FixedFormat

/** One per-joint figure of the monitor's state, as the register map and the summary name it. */
sealed abstract class JointField(val name: String, val meaning: String)

object JointField {
  case object Samples
      extends JointField("samples", "in-range valid samples since clear (sum dt = samples x sample period)")
  case object OutOfRangeSamples
      extends JointField("out_of_range_samples", "valid samples flagged out of range (counted only)")
  case object PeakTorque
      extends JointField("peak_torque", "largest signed torque code since clear (torque format)")
  case object MinTorque
      extends JointField("min_torque", "smallest signed torque code since clear (torque format)")
  case object RepeatedPeakSamples extends JointField("repeated_peak_samples", "samples with |tau| > T_R")
  case object MomentaryPeakEvents
      extends JointField("momentary_peak_events", "runs of consecutive samples with |tau| > T_M")
  case object LastEventPeak
      extends JointField(
        "last_event_peak_abs",
        "largest |tau| code of the last (or current) momentary-peak event"
      )
  case object LastEventDuration
      extends JointField("last_event_duration", "samples in the last (or current) momentary-peak event")
  case object LastEventSpeed
      extends JointField("last_event_speed_abs", "|qd| code at the last event's peak (velocity format)")
  case object Flags
      extends JointField(
        "flags",
        "bit 0: |tau| > T_R seen, bit 1: |tau| > T_M seen, bit 2: event in progress, bit " +
          "3: a histogram counter saturated"
      )
  case object DamageSum
      extends JointField(
        "damage_sum",
        "sum of |qd code| x power (u^p x 2^valueFracBits, u = |tau| / full scale; see the power table line)"
      )
  case object SpeedSum extends JointField("speed_sum", "sum of |qd code|")
  final case class HistogramBin(bin: Int)
      extends JointField(s"histogram_$bin", s"samples with |tau| in bin $bin (saturating)")

  /** Every field but the histogram, in register-map order. */
  val scalars: Seq[JointField] = Seq(
    Samples,
    OutOfRangeSamples,
    PeakTorque,
    MinTorque,
    RepeatedPeakSamples,
    MomentaryPeakEvents,
    LastEventPeak,
    LastEventDuration,
    LastEventSpeed,
    Flags,
    DamageSum,
    SpeedSum
  )

  object FlagBit {
    val repeatedPeakSeen = 0
    val momentaryPeakSeen = 1
    val inEvent = 2
    val histogramSaturated = 3
    val count = 4
  }
}

/** What a register holds: a monitor-wide word or a field of one joint. */
sealed trait RegisterKey
object RegisterKey {

  /**
   * Constant: 0x524D0000 + joint count ("RM"), so a host can check it talks to the monitor it was built for.
   */
  case object Id extends RegisterKey

  /**
   * Snapshots taken since reset, modulo 2^32: read it before and after a bank read to detect a snapshot in
   * between.
   */
  case object SnapshotCount extends RegisterKey
  final case class Joint(joint: Int, field: JointField) extends RegisterKey
}

/**
 * One entry of the register map: `words` consecutive 32-bit words from `address` (word address; byte address
 * \= 4 x address), least significant word first, a `width`-bit value zero- or sign-extended to whole words.
 */
final case class RegisterEntry(
    address: Int,
    key: RegisterKey,
    name: String,
    width: Int,
    signed: Boolean,
    meaning: String
) {
  val words: Int = (width + 31) / 32

  /** The value's 32-bit words, least significant first. */
  def encode(value: BigInt): Seq[BigInt] = {
    require(
      if (signed) value.bitLength < width else value >= 0 && value.bitLength <= width,
      s"register $name: $value does not fit ${if (signed) "signed" else "unsigned"} $width bits"
    )
    val raw = if (value < 0) value + (BigInt(1) << (32 * words)) else value
    (0 until words).map(i => (raw >> (32 * i)) & RegisterMap.wordMask)
  }

  /** The value back from its words. */
  def decode(ws: Seq[BigInt]): BigInt = {
    require(ws.size == words, s"register $name: ${ws.size} words, expected $words")
    val raw = ws.zipWithIndex.map { case (w, i) => w << (32 * i) }.sum
    if (signed) FixedFormat.fromTwosComplement(raw, 32 * words) else raw
  }
}

/** The host's view of the shadow bank: addresses assigned in order, no gaps. */
final case class RegisterMap(entries: Seq[RegisterEntry]) {
  val words: Int = entries.map(_.words).sum
  private val byKey: Map[RegisterKey, RegisterEntry] = entries.map(e => e.key -> e).toMap
  def apply(key: RegisterKey): RegisterEntry =
    byKey.getOrElse(key, throw new NoSuchElementException(s"no register for $key"))

  /**
   * Markdown table lines: address (word and byte), name, width, meaning (| escaped: |tau| is not a cell
   * border).
   */
  def markdown: Seq[String] =
    Seq("| word | byte | name | bits | words | meaning |", "| --- | --- | --- | --- | --- | --- |") ++
      entries.map { e =>
        f"| ${e.address}%d | 0x${4 * e.address}%04x | `${e.name}` | ${e.width}${if (e.signed) " signed"
          else ""} | ${e.words} | ${e.meaning.replace("|", "\\|")} |"
      }

  /** The whole bank as words, from a value per register. */
  def encode(value: RegisterKey => BigInt): IndexedSeq[BigInt] =
    entries.flatMap(e => e.encode(value(e.key))).toIndexedSeq

  /** Register values back from the bank's words. */
  def decode(bank: IndexedSeq[BigInt]): Map[RegisterKey, BigInt] = {
    require(bank.size == words, s"register bank of ${bank.size} words, the map has $words")
    entries.map(e => e.key -> e.decode(bank.slice(e.address, e.address + e.words))).toMap
  }
}

object RegisterMap {
  val wordMask: BigInt = (BigInt(1) << 32) - 1
  val idBase: BigInt = BigInt(0x524d0000L)

  /** Lay out (key, name, width, signed, meaning) rows one after the other. */
  def layout(rows: Seq[(RegisterKey, String, Int, Boolean, String)]): RegisterMap = {
    val addresses = rows.scanLeft(0) { case (a, (_, _, width, _, _)) => a + (width + 31) / 32 }
    RegisterMap(rows.zip(addresses).map { case ((k, n, w, s, m), a) => RegisterEntry(a, k, n, w, s, m) })
  }
}
