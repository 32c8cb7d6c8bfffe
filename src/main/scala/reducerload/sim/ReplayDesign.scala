package reducerload.sim

/**
 * A design as `run simulate` replays it, whatever engine runs it: the trajectory's columns and declared
 * ranges, a row (values in `columns` order) to input codes, the bit-accurate model, the harness ports, and
 * one result line per sample. The RTL engine and the model engine share all of it, so their files can differ
 * only where the RTL and the model do.
 */
trait ReplayDesign[In, Out] {

  /** Required trajectory columns, in the order a row is given. */
  def columns: Seq[String]

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
