package reducerload.trace

import ch.randelshofer.fastdoubleparser.JavaDoubleParser
import reducerload.util.InputError

/**
 * One logical CSV record: a `#` comment line or a row of cells, with the file line it starts on (1-based).
 */
sealed trait CsvRecord { def line: Int }
object CsvRecord {
  final case class Comment(line: Int, text: String) extends CsvRecord
  final case class Cells(line: Int, cells: IndexedSeq[String]) extends CsvRecord
}

/**
 * The longest record (a line, or the lines of a record with quoted line breaks) a [[CsvRecordReader]]
 * accepts, and what the limit is derived from, for the refusal. Bounded so that a file of one enormous line
 * is refused as soon as the reader has scanned past the limit, before any cell of it becomes a string.
 */
final case class RecordLimit(chars: Int, basis: String)
object RecordLimit {
  val none: RecordLimit = RecordLimit(Int.MaxValue, "no limit")

  /** The header (and comment lines before it): a megabyte holds thousands of long column names. */
  val header: RecordLimit = RecordLimit(1 << 20, "the limit for a header line")

  /**
   * A data row of `columns` cells: 1,024 characters per cell (a double takes at most 25; blanks, quotes and a
   * comment line of text fit too) plus 4,096.
   */
  def rows(columns: Int): RecordLimit =
    RecordLimit(
      4096 + 1024 * columns,
      s"the limit for a row of $columns columns: 1,024 characters per column and 4,096"
    )
}

/**
 * Splits CSV text into records as spreadsheets and controllers write it (RFC 4180): fields separated by
 * commas, optionally in double quotes (a doubled quote inside stands for one quote; a quoted field may hold
 * commas and line breaks), lines ending in LF, CRLF or a lone CR. Blank lines are skipped; a line whose first
 * non-blank character is `#` is a comment. Cells are trimmed.
 *
 * Pull-based, so the caller can name the columns in errors once it has read the header. Reads `text` from
 * `from` to `until` (the whole text by default), whose first line is number `firstLine`. A record longer than
 * `limit` is refused with the file and its line.
 *
 * Kept over commons-csv, which builds a String per cell: one thread reads a million-row trajectory's rows in
 * 1.2 s here, 4.1 s with commons-csv 1.12.0 and the same cell parser (trace/DecimalBenchmark).
 */
final class CsvRecordReader(
    source: String,
    text: String,
    from: Int = 0,
    until: Int = -1,
    firstLine: Int = 1,
    limit: RecordLimit = RecordLimit.none
) {
  private val end = if (until < 0) text.length else until
  require(
    from >= 0 && from <= end && end <= text.length,
    s"CsvRecordReader: range $from until $until of ${text.length} characters"
  )
  private var pos = from
  private var line = firstLine // line of `pos`, counting LF, CRLF and lone CR as one break each

  /** Where the next record starts, and its line. */
  def position: Int = pos
  def lineNumber: Int = line

  private def atEnd: Boolean = pos >= end

  /** Where a record starting at `from` must end by (without overflowing). */
  private def stopFor(from: Int): Int = if (limit.chars >= end - from) end else from + limit.chars

  private def tooLong(recordLine: Int): Nothing =
    throw new InputError(s"$source:$recordLine: line longer than ${limit.chars} characters (${limit.basis})")
  private def isBreak(c: Char): Boolean = c == '\n' || c == '\r'

  /** Consume a line break at `pos` (CRLF counts once) and count it. */
  private def skipBreak(): Unit = {
    if (text.charAt(pos) == '\r' && pos + 1 < end && text.charAt(pos + 1) == '\n') pos += 2 else pos += 1
    line += 1
  }

  private def endOfPhysicalLine(from: Int, stop: Int = end): Int = {
    var i = from
    while (i < stop && !isBreak(text.charAt(i))) i += 1
    i
  }

  private def skipBlanks(): Unit = while (!atEnd && (text.charAt(pos) == ' ' || text.charAt(pos) == '\t'))
    pos += 1

  /**
   * The next record, or None at the end. `fieldName(i)` describes field i (0-based) in errors, e.g. "column
   * 'd1'" once the header is known.
   */
  def next(fieldName: Int => String): Option[CsvRecord] = {
    while (!atEnd) {
      val stop = stopFor(pos)
      val eol = endOfPhysicalLine(pos, stop)
      if (eol == stop && stop < end && !isBreak(text.charAt(stop))) tooLong(line)
      val physical = text.substring(pos, eol).trim
      if (physical.isEmpty || physical.startsWith("#")) {
        val record = if (physical.isEmpty) None else Some(CsvRecord.Comment(line, text.substring(pos, eol)))
        pos = eol
        if (!atEnd) skipBreak()
        if (record.isDefined) return record
      } else return Some(readCells(fieldName))
    }
    None
  }

  /**
   * The next record when it is a plain data row (the usual case, read without building strings): exactly
   * `count` unquoted numbers ([[DecimalCell]]), then a line break or the end. Fills `into(at until at +
   * count)` and returns the row's line; otherwise returns -1 and consumes nothing (it may have written some
   * of `into`'s slots), and [[next]] reads the record (a comment, a blank line, quotes, a bad cell, a wrong
   * count) by the full rules.
   */
  def nextNumbers(into: Array[Double], at: Int, count: Int): Int = {
    var i = pos
    val stop = stopFor(pos) // a longer line is left to next(), which refuses it
    var k = 0
    while (k < count) {
      val from = i
      while (i < stop && { val c = text.charAt(i); c != ',' && c != '"' && !isBreak(c) }) i += 1
      if (i < end && text.charAt(i) == '"') return -1
      val v = DecimalCell.parse(text, from, i)
      if (v.isNaN) return -1
      into(at + k) = v
      k += 1
      if (k < count) {
        if (i < end && text.charAt(i) == ',') i += 1 else return -1
      }
    }
    if (i < end && !isBreak(text.charAt(i))) return -1
    val rowLine = line
    pos = i
    if (!atEnd) skipBreak()
    rowLine
  }

  private def readCells(fieldName: Int => String): CsvRecord = {
    val start = line
    val stop = stopFor(pos) // next() has checked the first line; quoted line breaks may extend the record
    val cells = IndexedSeq.newBuilder[String]
    var field = 0
    var more = true
    while (more) {
      skipBlanks()
      val cell =
        if (!atEnd && text.charAt(pos) == '"') readQuoted(fieldName(field), start, stop)
        else {
          val from = pos
          while (!atEnd && text.charAt(pos) != ',' && !isBreak(text.charAt(pos))) pos += 1
          text.substring(from, pos)
        }
      cells += cell.trim
      field += 1
      if (!atEnd && text.charAt(pos) == ',') pos += 1
      else {
        if (!atEnd) skipBreak()
        more = false
      }
    }
    CsvRecord.Cells(start, cells.result())
  }

  /** A quoted field from its opening quote; leaves `pos` at the comma or line break after it. */
  private def readQuoted(name: String, recordLine: Int, stop: Int): String = {
    val openedOn = line
    val sb = new StringBuilder
    pos += 1
    var closed = false
    while (!closed) {
      if (pos >= stop && stop < end) tooLong(recordLine)
      if (atEnd)
        throw new InputError(
          s"$source:$openedOn: $name: unterminated quoted field (the '\"' opened on line $openedOn is never closed)"
        )
      val c = text.charAt(pos)
      if (c == '"') {
        if (pos + 1 < end && text.charAt(pos + 1) == '"') { sb += '"'; pos += 2 }
        else { pos += 1; closed = true }
      } else if (isBreak(c)) {
        // A line break inside quotes belongs to the field; count it so later lines keep their numbers.
        sb += '\n'
        skipBreak()
      } else { sb += c; pos += 1 }
    }
    skipBlanks()
    if (!atEnd && text.charAt(pos) != ',' && !isBreak(text.charAt(pos)))
      throw new InputError(
        s"$source:$line: $name: unexpected text after a closing quote " +
          s"('${TraceCsv.printable(text.substring(pos, endOfPhysicalLine(pos, math.min(end, pos + 100))))}'; a quote inside a quoted field is written twice)"
      )
    sb.result()
  }
}

object CsvRecordReader {

  /**
   * Line breaks in `text(from until until)`: LF, CRLF and lone CR count one each (CRLF must not straddle
   * `until`).
   */
  def lineBreaks(text: String, from: Int, until: Int): Int = {
    var count = 0 // runtime loop state
    var i = from
    while (i < until) {
      val c = text.charAt(i)
      if (c == '\n' || (c == '\r' && !(i + 1 < until && text.charAt(i + 1) == '\n'))) count += 1
      i += 1
    }
    count
  }
}

/**
 * The number in a CSV cell, read straight from the text: what [[TraceCsv.parseNumber]] returns for the
 * trimmed cell, without a substring or a regular expression. Blanks (space, tab) around the number are
 * allowed, as the reader trims them. Anything else (an empty cell, other characters, an infinite value) gives
 * NaN, which [[TraceCsv.parseNumber]] never returns: the caller then takes the general path, which explains
 * the problem in its error message.
 */
object DecimalCell {

  /**
   * The number in `text(from until until)`, or NaN; correctly rounded, like `parseDouble`. FastDoubleParser
   * reads Java's literal grammar (NaN, Infinity, hexadecimal, a d or f suffix too), so only TraceCsv's
   * characters (digits, sign, point, exponent, blanks) go to it.
   */
  def parse(text: CharSequence, from: Int, until: Int): Double = {
    var i = from
    while (i < until) {
      val c = text.charAt(i)
      if (
        !((c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E' || c == ' ' || c == '\t')
      )
        return Double.NaN
      i += 1
    }
    try {
      val v = JavaDoubleParser.parseDouble(text, from, until - from)
      if (v.isInfinite) Double.NaN else v
    } catch { case _: NumberFormatException => Double.NaN }
  }
}
