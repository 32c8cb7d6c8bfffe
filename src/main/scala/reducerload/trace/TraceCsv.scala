package reducerload.trace

import java.nio.charset.{CharacterCodingException, CodingErrorAction, StandardCharsets}
import java.io.{ByteArrayInputStream, IOException}
import java.nio.file.{Files, Path}
import java.util.zip.GZIPInputStream
import scala.collection.immutable.ArraySeq
import reducerload.util.ChunkedRun
import reducerload.util.{InputError, InputFile}

import scala.util.Try

/**
 * A numeric CSV table: optional `#` comment lines, one header row, then rows of finite numbers. Row numbers
 * in errors are the file's line numbers (1-based). Fields may be quoted (RFC 4180), lines may end in LF, CRLF
 * or CR, and a UTF-8 byte-order mark is ignored (see [[CsvRecordReader]]).
 *
 * The rows are kept flat, with no object per row (a million-row trajectory would otherwise be millions of
 * small objects for the collector): row r's value in column c is `values(r * header.size + c)`, and row r
 * starts on file line `lines(r)`. Treat both arrays as read-only.
 */
final class TraceTable(
    val source: String,
    val comments: Seq[String],
    val header: IndexedSeq[String],
    val headerLine: Int,
    val lines: Array[Int],
    val values: Array[Double]
) {
  require(
    values.length == lines.length * header.size,
    s"TraceTable: ${values.length} values for ${lines.length} rows of ${header.size}"
  )

  def width: Int = header.size
  def size: Int = lines.length

  /** Row `r`'s values (a copy). */
  def row(r: Int): IndexedSeq[Double] =
    ArraySeq.unsafeWrapArray(java.util.Arrays.copyOfRange(values, r * width, (r + 1) * width))

  /** (file line, values) of every row, built on demand (one object per row: for small tables and tests). */
  def rows: IndexedSeq[(Int, IndexedSeq[Double])] = IndexedSeq.tabulate(size)(r => lines(r) -> row(r))

  def column(name: String): IndexedSeq[Double] = {
    val i = header.indexOf(name)
    if (i < 0)
      throw new InputError(
        s"$source: no column '$name' (header: ${TraceCsv.printable(header.mkString(","))})"
      )
    ArraySeq.unsafeWrapArray(Array.tabulate(size)(r => values(r * width + i)))
  }

  def has(name: String): Boolean = header.contains(name)

  /** `key=value` pairs from a comment line `# <tag>: k=v k=v`. */
  def commentFields(tag: String): Map[String, String] =
    comments
      .map(_.stripPrefix("#").trim)
      .find(_.startsWith(tag + ":"))
      .toSeq
      .flatMap { line =>
        line.stripPrefix(tag + ":").trim.split("\\s+").toSeq.flatMap { kv =>
          kv.split("=", 2) match {
            case Array(k, v) => Some(k -> v)
            case _           => None
          }
        }
      }
      .toMap
}

/** A growing flat array of rows (values and their lines), for one segment of the file. */
private final class RowBuffer(width: Int, expectedRows: Int) {
  var values = new Array[Double](math.max(expectedRows, 1) * width)
  var lines = new Array[Int](math.max(expectedRows, 1))
  var size = 0

  /** Room for one more row at `size * width`. */
  def reserve(): Unit = if (size == lines.length) {
    lines = java.util.Arrays.copyOf(lines, lines.length * 2)
    values = java.util.Arrays.copyOf(values, lines.length * width)
  }

  def add(line: Int, row: Array[Double]): Unit = {
    reserve()
    System.arraycopy(row, 0, values, size * width, width)
    lines(size) = line
    size += 1
  }
}

object TraceCsv {
  private val decimal = "[+-]?([0-9]+[.]?[0-9]*|[.][0-9]+)([eE][+-]?[0-9]+)?".r

  /** A finite decimal number, strictly (no Java suffixes like 1f, no NaN or Infinity, no overflow to Inf). */
  def parseNumber(cell: String): Option[Double] =
    if (decimal.matches(cell)) Some(cell.toDouble).filter(v => !v.isInfinite) else None

  /**
   * A value quoted in an error message: its first 40 characters, then its length when it is longer (a header
   * of 100 MB must not become a 100 MB message); control characters shown as '?', so the message stays one
   * line.
   */
  private[trace] def printable(s: String): String =
    if (s.length <= 40) oneLine(s) else s"${oneLine(s.take(40))}... (${s.length} characters)"

  /** Control characters (a line break inside a quoted header cell, say) shown as '?'. */
  private def oneLine(s: String): String = s.map(c => if (c.isControl) '?' else c)

  /**
   * Excel's "CSV UTF-8" starts the file with a byte-order mark; it is not part of the first column's name.
   */
  private val byteOrderMark = '\uFEFF'

  private val numbered = "(\\D*)([0-9]+)".r

  /**
   * Refuse a column that looks like a joint column of `columns` (one of their names' prefixes and a number:
   * q4, qd4, qdd4 beside q1..q3) but is none of them: a different robot's recording must not pass with its
   * extra joints ignored. `columns`' highest number is the robot's joint count.
   */
  def checkJointColumns(table: TraceTable, columns: Seq[String]): Unit = {
    val joints = columns.collect { case numbered(prefix, k) => prefix -> k.toInt }
    val prefixes = joints.map(_._1).distinct
    val n = if (joints.isEmpty) 0 else joints.map(_._2).max
    table.header
      .filterNot(columns.contains)
      .collectFirst {
        case h @ numbered(prefix, k) if prefixes.contains(prefix) => (h, k.toInt)
      }
      .foreach { case (h, k) =>
        throw new InputError(
          s"${table.source}:${table.headerLine}: column '${printable(h)}' is for joint $k, but the robot has $n joints " +
            s"(columns ${prefixes.map(p => s"${p}1..$p$n").mkString(", ")}); a trajectory of another robot?"
        )
      }
  }

  /** A file whose name ends in `.gz` is gzip-compressed (e.g. `traj.csv.gz`), decompressed in memory. */
  def isGzip(path: Path): Boolean = path.getFileName.toString.toLowerCase.endsWith(".gz")

  private def gunzip(source: String, bytes: Array[Byte]): Array[Byte] =
    try {
      // The constructor already reads the header, so it belongs inside the try.
      val in = new GZIPInputStream(new ByteArrayInputStream(bytes))
      try in.readAllBytes()
      finally in.close()
    } catch {
      // ZipException (bad header or data) and EOFException (truncated) are both IOExceptions.
      case e: IOException =>
        val why = Option(e.getMessage).filter(_.nonEmpty).getOrElse(e.getClass.getSimpleName)
        throw new InputError(s"$source: not a valid gzip file (${printable(why)})")
    }

  def read(path: Path, required: Seq[String]): TraceTable = {
    val source = path.toString
    InputFile.check(path, source)
    val raw = Files.readAllBytes(path)
    val bytes = if (isGzip(path)) gunzip(source, raw) else raw
    val text =
      // Plain ASCII (the usual trajectory) is valid UTF-8 as it is: no decoder pass.
      if (isAscii(bytes)) new String(bytes, StandardCharsets.ISO_8859_1)
      else
        try
          StandardCharsets.UTF_8
            .newDecoder()
            .onMalformedInput(CodingErrorAction.REPORT)
            .decode(java.nio.ByteBuffer.wrap(bytes))
            .toString
        catch {
          case _: CharacterCodingException =>
            throw new InputError(s"$source: not a text file (invalid UTF-8)")
        }
    if (text.contains('\u0000')) throw new InputError(s"$source: not a text file (contains NUL bytes)")
    parse(source, text, required)
  }

  private def isAscii(bytes: Array[Byte]): Boolean = {
    var i = 0
    while (i < bytes.length && bytes(i) >= 0) i += 1
    i == bytes.length
  }

  def parse(source: String, text: String, required: Seq[String]): TraceTable =
    parse(source, text, required, 1 << 22)

  /**
   * [[parse]], the data after the header split into segments of about `segmentChars` characters, read in
   * parallel; the header line at most `headerLimit` long, a data line at most `rowLimit(columns)`.
   */
  private[trace] def parse(
      source: String,
      text: String,
      required: Seq[String],
      segmentChars: Int,
      headerLimit: RecordLimit = RecordLimit.header,
      rowLimit: Int => RecordLimit = RecordLimit.rows
  ): TraceTable = {
    require(segmentChars >= 1, s"segmentChars must be >= 1, got $segmentChars")
    val body = text.stripPrefix(byteOrderMark.toString)
    val reader = new CsvRecordReader(source, body, limit = headerLimit)
    val comments = Vector.newBuilder[String]
    val (headerLine, header) = nextCells(reader, comments, i => s"header field ${i + 1}") match {
      case Some(CsvRecord.Cells(line, cells)) => (line, cells)
      case None =>
        throw new InputError(s"$source: empty (a header row ${required.mkString(",")} is required)")
    }
    if (header.exists(h => h.nonEmpty && Try(h.toDouble).isSuccess))
      throw new InputError(
        s"$source:$headerLine: the first row must be a header (${required.mkString(",")}), got numbers"
      )
    header.groupBy(identity).collectFirst { case (h, hs) if hs.size > 1 => h }.foreach { dup =>
      throw new InputError(s"$source:$headerLine: column '${printable(dup)}' appears twice in the header")
    }
    val missing = required.filterNot(header.contains)
    if (missing.nonEmpty)
      throw new InputError(
        s"$source:$headerLine: missing column(s) ${missing.map("'" + _ + "'").mkString(", ")} (header: ${printable(header.mkString(","))})"
      )
    // Without quotes after the header every LF ends a record: the data splits into segments after
    // LFs, each read on its own (line numbers counted first); the earliest segment's error wins.
    val segments =
      if (body.indexOf('"', reader.position) >= 0) Seq(reader.position -> body.length)
      else {
        val cuts = Iterator
          .iterate(reader.position)(at =>
            if (segmentChars >= body.length - at) body.length
            else
              body.indexOf('\n', at + segmentChars) match {
                case -1 => body.length
                case lf => lf + 1
              }
          )
          .takeWhile(_ < body.length)
          .toSeq :+ body.length
        cuts.zip(cuts.tail)
      }
    val jobs = Runtime.getRuntime.availableProcessors.max(1)
    val firstLines = ChunkedRun(segments.size, 1, jobs)(r =>
      CsvRecordReader.lineBreaks(body, segments(r.head)._1, segments(r.head)._2)
    )
      .scanLeft(reader.lineNumber)(_ + _)
    val parts = ChunkedRun(segments.size, 1, jobs) { r =>
      val (from, until) = segments(r.head)
      val segmentComments = Vector.newBuilder[String]
      // At most one row per line (the segment's line breaks, plus a last line without one).
      val buffer = new RowBuffer(header.size, firstLines(r.head + 1) - firstLines(r.head) + 1)
      readRows(
        source,
        new CsvRecordReader(source, body, from, until, firstLines(r.head), rowLimit(header.size)),
        header,
        segmentComments,
        buffer
      )
      (segmentComments.result(), buffer)
    }
    parts.foreach(p => comments ++= p._1)
    val count = parts.map(_._2.size).sum
    if (count == 0) throw new InputError(s"$source: no data rows after the header")
    val lines = new Array[Int](count)
    val values = new Array[Double](count * header.size)
    var at = 0
    parts.foreach { case (_, b) =>
      System.arraycopy(b.lines, 0, lines, at, b.size)
      System.arraycopy(b.values, 0, values, at * header.size, b.size * header.size)
      at += b.size
    }
    new TraceTable(source, comments.result(), header, headerLine, lines, values)
  }

  /** The next row of cells; comment lines on the way go to `comments`. */
  @annotation.tailrec
  private def nextCells(
      reader: CsvRecordReader,
      comments: collection.mutable.Growable[String],
      fieldName: Int => String
  ): Option[CsvRecord.Cells] =
    reader.next(fieldName) match {
      case Some(CsvRecord.Comment(_, c)) => comments += c; nextCells(reader, comments, fieldName)
      case Some(cells: CsvRecord.Cells)  => Some(cells)
      case None                          => None
    }

  /**
   * Every data row `reader` has left: plain rows by its fast path, any other record (comments, quotes,
   * errors) by the general one.
   */
  private def readRows(
      source: String,
      reader: CsvRecordReader,
      header: IndexedSeq[String],
      comments: collection.mutable.Growable[String],
      into: RowBuffer
  ): Unit = {
    val columnName = (i: Int) =>
      if (i < header.size) s"column '${printable(header(i))}'" else s"field ${i + 1}"
    def numbers(lineNo: Int, cells: IndexedSeq[String]): Array[Double] = {
      if (cells.size != header.size)
        throw new InputError(s"$source:$lineNo: ${cells.size} values, the header has ${header.size} columns")
      cells
        .zip(header)
        .map { case (cell, col) =>
          parseNumber(cell).getOrElse {
            val what =
              if (cell.toLowerCase.matches("[+-]?(nan|inf|infinity)")) "is not a finite number"
              else "is not a number"
            throw new InputError(s"$source:$lineNo: column '${printable(col)}': '${printable(cell)}' $what")
          }
        }
        .toArray
    }
    val width = header.size
    var more = true // runtime loop state
    while (more) {
      into.reserve()
      // Straight into the buffer; the row counts only once the reader says it was a plain row.
      val fast = reader.nextNumbers(into.values, into.size * width, width)
      if (fast >= 0) { into.lines(into.size) = fast; into.size += 1 }
      else
        nextCells(reader, comments, columnName) match {
          case Some(CsvRecord.Cells(lineNo, cells)) => into.add(lineNo, numbers(lineNo, cells))
          case None                                 => more = false
        }
    }
  }
}
