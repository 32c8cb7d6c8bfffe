package reducerload.sim

import scala.collection.immutable.ArraySeq

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
