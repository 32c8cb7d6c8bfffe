package reducerload.app

import reducerload.arm.PayloadColumns
import reducerload.trace.{TraceCsv, TraceTable}
import reducerload.util.{InputError, Warning}

/**
 * Where a replay's payload comes from: the trajectory's payload columns (all ten, per row: a pick-and-place
 * recording), `--payload` (one payload for the whole replay), or neither (no payload: every parameter 0, with
 * a warning). A design without a run-time payload takes neither.
 */
sealed trait ReplayPayload
object ReplayPayload {

  /** Per row, from the file's payload columns. */
  case object Columns extends ReplayPayload

  /** One payload for every row (`--payload`, or none), in [[PayloadColumns]]' order. */
  final case class Constant(values: Seq[Double]) extends ReplayPayload

  /** The payload given to a design with none: nothing. */
  case object Absent extends ReplayPayload

  val option: Opt = Opt(
    "payload",
    PayloadColumns.names.map(_.stripPrefix("payload_").toUpperCase).mkString(","),
    "with payload.enabled: the payload of the whole replay, ten numbers in the order of the payload columns " +
      s"(${PayloadColumns.names.mkString(",")}: kg, m in the payload frame, kg m^2 about the centre of mass); " +
      "instead, the trajectory may carry those columns (per row); neither: no payload, with a warning"
  )

  /** The ten numbers of `--payload`. */
  def parse(value: String): Seq[Double] = {
    val cells = value.split(",", -1).map(_.trim).toSeq
    if (cells.size != PayloadColumns.names.size)
      throw new InputError(
        s"command line: --payload takes ${PayloadColumns.names.size} numbers (${PayloadColumns.names.mkString(",")}), got ${cells.size}"
      )
    cells.zip(PayloadColumns.names).map { case (cell, name) =>
      TraceCsv
        .parseNumber(cell)
        .getOrElse(
          throw new InputError(s"command line: --payload: $name: '${cell.take(40)}' is not a number")
        )
    }
  }

  /**
   * The payload of a replay of `table` by a design whose payload columns are `columns` (none: no payload),
   * with `flag` the value of `--payload`; a refusal is one line naming the file or the option.
   */
  def resolve(table: TraceTable, columns: Seq[String], flag: Option[String]): ReplayPayload = {
    val inFile = PayloadColumns.names.filter(table.has)
    val where = s"${table.source}:${table.headerLine}"
    if (columns.isEmpty) {
      inFile.headOption.foreach(c =>
        throw new InputError(
          s"$where: column '$c': the design has no run-time payload (payload.enabled = true replays payloads)"
        )
      )
      flag.foreach(_ =>
        throw new InputError(
          "command line: --payload needs a design with a run-time payload (payload.enabled = true)"
        )
      )
      Absent
    } else {
      val missing = columns.filterNot(table.has)
      if (inFile.nonEmpty && missing.nonEmpty)
        throw new InputError(
          s"$where: payload columns are all ${columns.size} or none: missing ${missing.map("'" + _ + "'").mkString(", ")}"
        )
      (inFile.nonEmpty, flag) match {
        case (true, Some(_)) =>
          throw new InputError(
            s"command line: --payload and the payload columns of ${table.source} both give the payload; give one"
          )
        case (true, None)     => Columns
        case (false, Some(v)) => Constant(parse(v))
        case (false, None) =>
          Console.err.println(
            Warning(
              table.source,
              "no payload given (--payload or the payload columns): replayed with no payload (every parameter 0)"
            )
          )
          Constant(Seq.fill(columns.size)(0.0))
      }
    }
  }
}
