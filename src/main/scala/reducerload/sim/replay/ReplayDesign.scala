package reducerload.sim.replay

import reducerload.arm.{ArmTrajectory, PayloadColumns}
import reducerload.config.LoadParams
import reducerload.load.Joint3Columns
import reducerload.sim.rtl.HarnessPorts
import reducerload.sim.text.{DoubleText, FixedDecimal}

import scala.collection.immutable.ArraySeq

/**
 * A design as `run simulate` replays it, whatever engine runs it: the trajectory's columns and declared
 * ranges, a row (values in `columns` order) to input codes, the bit-accurate model, the harness ports, and
 * one result line per sample. The RTL engine and the model engine share all of it, so their files can differ
 * only where the RTL and the model do.
 */
trait ReplayDesign[In, Out] {

  /** The trajectory's columns: what [[ReplayColumns.of]] gives for the design's settings. */
  def layout: ReplayColumns

  /** Required trajectory columns, in the order a row is given. */
  final def columns: Seq[String] = layout.columns

  /**
   * The columns of `columns` that give the run-time payload (all or none from the file; `--payload` gives
   * them for a whole replay); none for a design without a payload.
   */
  final def payloadColumns: Seq[String] = layout.payloadColumns

  /** (index into `columns`, declared max |value|) of every range-checked column. */
  def limits: Seq[(Int, Double)]

  def encode(row: IndexedSeq[Double]): In
  def evaluate(in: In): Out

  def ports: HarnessPorts
  def harnessValues(in: In): Seq[BigInt]
  def fromHarness(values: IndexedSeq[BigInt]): Out

  /** Clocks between samples the design takes, and from a sample to its result. */
  def samplePeriod: Int
  def latency: Int

  def outputHeader: String

  /**
   * Append sample `index`'s output line (no line end; the hardware's values by [[FixedDecimal]], the
   * reference and the error by [[DoubleText]]) to `text` and its |error| per [[errorLabels]] entry to
   * `errors`; returns whether it was flagged out of range.
   */
  def result(
      index: Long,
      row: IndexedSeq[Double],
      out: Out,
      text: java.lang.StringBuilder,
      errors: Array[Double]
  ): Boolean

  /** The same replay in primitive arrays, when the design has one. */
  def arrays: Option[ArrayReplay] = None

  /** What the `errors` of [[result]] are about, and each one's derived bound (N·m). */
  def errorLabels: IndexedSeq[String]
  def errorBounds: IndexedSeq[Double]

  /** One line for the summary: what was computed. */
  def description: String

  /** How the design takes samples, for the rate line. */
  def throughput: String
}

/**
 * A [[ReplayDesign]]'s replay in primitive arrays (what `run simulate` runs when the design offers it): codes
 * and outputs as longs in the harness ports' order, one [[ArrayReplay.Worker]] of work arrays per thread, no
 * allocation per sample. It writes the same lines as the design's `encode` / `evaluate` / `result`
 * (SimulateEnginesSpec, ReplayArraysSpec).
 */
trait ArrayReplay {

  /** Codes per sample, in the order of the harness's input ports. */
  def inputCount: Int

  /** Values per sample, in the order of the harness's output ports. */
  def outputCount: Int
  def worker(): ArrayReplay.Worker
}

object ArrayReplay {
  trait Worker {

    /** The codes of the row at `rows(row ..)` (values in the design's column order) to `codes(at ..)`. */
    def encode(rows: Array[Double], row: Int, codes: Array[Long], at: Int): Unit

    /** The bit-accurate model of the codes at `codes(at ..)`, to `out(outAt ..)`. */
    def evaluate(codes: Array[Long], at: Int, out: Array[Long], outAt: Int): Unit

    /** [[ReplayDesign.result]] of the row at `rows(row ..)` and the outputs at `out(outAt ..)`. */
    def result(
        index: Long,
        rows: Array[Double],
        row: Int,
        out: Array[Long],
        outAt: Int,
        text: java.lang.StringBuilder,
        errors: Array[Double]
    ): Boolean
  }
}

/**
 * The trajectory columns of a design as its settings give them, known before it is compiled (so `run
 * simulate` reads and checks its input before the device fit): `columns` in the order a row is given,
 * `payloadColumns` those of them that give the run-time payload. A [[ReplayDesign]] takes its own from here.
 */
final case class ReplayColumns(columns: Seq[String], payloadColumns: Seq[String]) {
  require(payloadColumns.forall(columns.contains), s"ReplayColumns: $payloadColumns not all in $columns")

  /** The columns a file must have (a payload may come from `--payload` instead). */
  def required: Seq[String] = columns.filterNot(payloadColumns.contains)
}

object ReplayColumns {

  /**
   * Every joint of an arm: q1..qN,qd1..qdN,qdd1..qddN, then the ten payload columns with a run-time payload.
   */
  def arm(joints: Int, payload: Boolean): ReplayColumns = {
    val extra = if (payload) PayloadColumns.names else Nil
    ReplayColumns(ArmTrajectory.columns(joints) ++ extra, extra)
  }

  /** The joint-3 closed forms' trace columns. */
  val joint3: ReplayColumns = ReplayColumns(Joint3Columns.names, Nil)

  /** The columns of the design `p` describes (reads its robot's chain, nothing more). */
  def of(p: LoadParams): ReplayColumns =
    if (p.model.closedForm) joint3 else arm(p.robot.chain.size, p.payload.enabled)
}

/**
 * A trajectory as `run simulate` replays it, flat: `size` rows of `width` values (a design's columns, in its
 * order), row r at `values(r * width until (r + 1) * width)`; no object per row. Treat `values` as read-only.
 */
final class SampleRows(val width: Int, val values: Array[Double]) {
  require(width >= 1 && values.length % width == 0, s"SampleRows: ${values.length} values in rows of $width")

  val size: Int = values.length / width

  /** Where row `r` starts in `values`. */
  def offset(r: Int): Int = r * width

  /** Row `r`'s values (a copy, for the general path and the tests). */
  def row(r: Int): IndexedSeq[Double] =
    ArraySeq.unsafeWrapArray(java.util.Arrays.copyOfRange(values, r * width, (r + 1) * width))
}

object SampleRows {

  /** Rows given as sequences (tests, small inputs). */
  def of(rows: Seq[Seq[Double]]): SampleRows = {
    require(rows.nonEmpty, "SampleRows.of: no rows")
    val width = rows.head.size
    require(rows.forall(_.size == width), "SampleRows.of: rows of different widths")
    new SampleRows(width, rows.flatten.toArray)
  }
}
