package reducerload.trace

import java.nio.charset.{CharacterCodingException, CodingErrorAction, StandardCharsets}
import java.nio.file.{Files, Path}
import scala.util.Try

/** A user error in an input file: one line naming the file, row and column. */
final class InputError(message: String) extends Exception(message)

/**
 * A numeric CSV table: optional `#` comment lines, one header row, then rows of finite numbers.
 * Row numbers in errors are the file's line numbers (1-based).
 */
final case class TraceTable(source: String, comments: Seq[String], header: IndexedSeq[String], rows: IndexedSeq[(Int, IndexedSeq[Double])]) {
  def column(name: String): IndexedSeq[Double] = {
    val i = header.indexOf(name)
    if (i < 0) throw new InputError(s"$source: no column '$name' (header: ${header.mkString(",")})")
    rows.map(_._2(i))
  }

  def has(name: String): Boolean = header.contains(name)

  /** `key=value` pairs from a comment line `# <tag>: k=v k=v`. */
  def commentFields(tag: String): Map[String, String] =
    comments.map(_.stripPrefix("#").trim).find(_.startsWith(tag + ":")).toSeq.flatMap { line =>
      line.stripPrefix(tag + ":").trim.split("\\s+").toSeq.flatMap { kv =>
        kv.split("=", 2) match {
          case Array(k, v) => Some(k -> v)
          case _           => None
        }
      }
    }.toMap
}

object TraceCsv {
  private val decimal = "[+-]?([0-9]+[.]?[0-9]*|[.][0-9]+)([eE][+-]?[0-9]+)?".r

  /** A finite decimal number, strictly (no Java suffixes like 1f, no NaN or Infinity, no overflow to Inf). */
  def parseNumber(cell: String): Option[Double] =
    if (decimal.matches(cell)) Some(cell.toDouble).filter(v => !v.isInfinite) else None

  private def printable(s: String): String = s.take(40).map(c => if (c.isControl) '?' else c)

  def read(path: Path, required: Seq[String]): TraceTable = {
    val source = path.toString
    if (!Files.isRegularFile(path)) throw new InputError(s"$source: no such file")
    val bytes = Files.readAllBytes(path)
    val text =
      try StandardCharsets.UTF_8.newDecoder().onMalformedInput(CodingErrorAction.REPORT).decode(java.nio.ByteBuffer.wrap(bytes)).toString
      catch { case _: CharacterCodingException => throw new InputError(s"$source: not a text file (invalid UTF-8)") }
    if (text.contains('\u0000')) throw new InputError(s"$source: not a text file (contains NUL bytes)")
    parse(source, text, required)
  }

  def parse(source: String, text: String, required: Seq[String]): TraceTable = {
    val lines = text.split("\r?\n", -1).toIndexedSeq.zipWithIndex.map { case (l, i) => (i + 1, l) }
    val (comments, rest) = lines.filter(_._2.trim.nonEmpty).partition(_._2.trim.startsWith("#"))
    if (rest.isEmpty) throw new InputError(s"$source: empty (a header row ${required.mkString(",")} is required)")
    val (headerLine, headerText) = rest.head
    val header = headerText.split(",", -1).map(_.trim).toIndexedSeq
    if (header.exists(h => h.nonEmpty && Try(h.toDouble).isSuccess))
      throw new InputError(s"$source:$headerLine: the first row must be a header (${required.mkString(",")}), got numbers")
    header.groupBy(identity).collectFirst { case (h, hs) if hs.size > 1 => h }.foreach { dup =>
      throw new InputError(s"$source:$headerLine: column '$dup' appears twice in the header")
    }
    val missing = required.filterNot(header.contains)
    if (missing.nonEmpty)
      throw new InputError(s"$source:$headerLine: missing column(s) ${missing.map("'" + _ + "'").mkString(", ")} (header: ${header.mkString(",")})")
    val rows = rest.tail.map { case (lineNo, line) =>
      val cells = line.split(",", -1).map(_.trim).toIndexedSeq
      if (cells.size != header.size)
        throw new InputError(s"$source:$lineNo: ${cells.size} values, the header has ${header.size} columns")
      lineNo -> cells.zip(header).map { case (cell, col) =>
        parseNumber(cell).getOrElse {
          val what = if (cell.toLowerCase.matches("[+-]?(nan|inf|infinity)")) "is not a finite number" else "is not a number"
          throw new InputError(s"$source:$lineNo: column '$col': '${printable(cell)}' $what")
        }
      }
    }
    if (rows.isEmpty) throw new InputError(s"$source: no data rows after the header")
    TraceTable(source, comments.map(_._2), header, rows)
  }
}
