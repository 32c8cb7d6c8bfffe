package reducerload.trace

import reducerload.util.InputError
import reducerload.testutil.Scratch
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.testutil.Seeds

import java.io.ByteArrayOutputStream
import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}
import java.util.zip.GZIPOutputStream
import scala.util.Random

/** Trajectory CSVs as spreadsheets and controllers write them; plain ScalaTest, no simulator. */
class TraceCsvSpec extends AnyFlatSpec {
  behavior of "TraceCsv"

  private val columns = Seq("t1", "t2", "t3", "d1", "d2", "d3", "dd1", "dd2", "dd3")
  private val header = columns.mkString(",")
  private val rowA = Seq("0.1", "0.2", "0.3", "1", "-1", "0.5", "2", "3", "-4")
  private val rowB = Seq("1.5", "-0.7", "2.9", "2.5", "0.5", "-1", "-9", "9", "1e-3")
  private val plainText = s"# robot: m3=10\n$header\n${rowA.mkString(",")}\n${rowB.mkString(",")}\n"
  private val plain = TraceCsv.parse("plain.csv", plainText, columns)

  private def tempFile(suffix: String, bytes: Array[Byte]): Path = {
    val f = Scratch.file("trace-", suffix)
    f.toFile.deleteOnExit()
    Files.write(f, bytes)
  }
  private def utf8(s: String): Array[Byte] = s.getBytes(StandardCharsets.UTF_8)
  private def gzip(bytes: Array[Byte]): Array[Byte] = {
    val out = new ByteArrayOutputStream()
    val z = new GZIPOutputStream(out)
    try z.write(bytes)
    finally z.close()
    out.toByteArray
  }

  /** Same header and values as the plain file (line numbers may differ). */
  private def sameAsPlain(t: TraceTable): Unit = {
    assert(t.header == plain.header)
    assert(t.rows.map(_._2) == plain.rows.map(_._2))
    columns.foreach(c => assert(t.column(c) == plain.column(c), s"column $c"))
  }

  /** An InputError of one line naming the source and every word. */
  private def refused(words: String*)(f: => Any): Unit = {
    val e = intercept[InputError](f)
    assert(!e.getMessage.contains("\n"), s"error spans lines: ${e.getMessage}")
    words.foreach(w => assert(e.getMessage.contains(w), s"'${e.getMessage}' does not mention '$w'"))
  }

  it should "read a plain file (the reference for the other forms)" in {
    assert(plain.rows.map(_._1) == Seq(3, 4))
    assert(plain.column("dd3") == Seq(-4.0, 1e-3))
    assert(plain.commentFields("robot") == Map("m3" -> "10"))
  }

  it should "keep the rows flat: one array of values, row after row, and one of their lines" in {
    assert(plain.size == 2 && plain.width == columns.size)
    assert(plain.lines.toSeq == Seq(3, 4))
    assert(plain.values.toSeq == (rowA ++ rowB).map(_.toDouble))
    // Quoted fields, comments between rows, extra columns and rows in many segments: the same layout.
    val mixed =
      s"$header,note\n${rowA.mkString(",")},1\n# between\n\n${rowB.map("\"" + _ + "\"").mkString(",")},\" 7\"\n" +
        (1 to 50).map(i => (rowA :+ i.toString).mkString(",")).mkString("", "\n", "\n")
    Seq(1, 7, 1 << 22).foreach { chars =>
      val t = TraceCsv.parse("mixed.csv", mixed, columns, chars)
      assert(t.size == 52 && t.width == columns.size + 1 && t.values.length == 52 * t.width)
      assert(t.lines.toSeq == Seq(2, 5) ++ (6 to 55), s"segments of $chars characters")
      assert(t.row(1) == rowB.map(_.toDouble) :+ 7.0)
      assert(t.rows.map(_._2) == (0 until t.size).map(t.row))
    }
  }

  it should "ignore a UTF-8 byte-order mark (Excel's CSV UTF-8), in a file and in text" in {
    val bom = Array(0xef, 0xbb, 0xbf).map(_.toByte)
    sameAsPlain(TraceCsv.read(tempFile(".csv", bom ++ utf8(plainText)), columns))
    sameAsPlain(TraceCsv.parse("bom.csv", "\uFEFF" + plainText, columns))
    // Without a comment line, the mark sits right before the first column's name.
    sameAsPlain(
      TraceCsv.read(tempFile(".csv", bom ++ utf8(plainText.linesIterator.drop(1).mkString("\n"))), columns)
    )
  }

  it should "read RFC 4180 quoted fields: quoted names and numbers, blanks around quotes, doubled quotes, commas inside" in {
    def q(cells: Seq[String]) = cells.map("\"" + _ + "\"").mkString(",")
    sameAsPlain(TraceCsv.parse("q.csv", s"${q(columns)}\n${q(rowA)}\n${rowB.mkString(",")}\n", columns))
    sameAsPlain(
      TraceCsv.parse(
        "q.csv",
        s"$header\n${rowA.map(c => s""" "$c" """).mkString(",")}\n${q(rowB)}\n",
        columns
      )
    )
    // An extra column whose name holds a comma and a doubled quote: one column, not two.
    val extra =
      TraceCsv.parse("q.csv", s"""$header,"note, with ""quotes""\"\n${rowA.mkString(",")},7\n""", columns)
    assert(extra.header.last == "note, with \"quotes\"")
    assert(extra.column("note, with \"quotes\"") == Seq(7.0))
    assert(extra.column("t1") == Seq(0.1))
    // A line break inside quotes stays in the field, and later rows keep their file line numbers.
    val multi = TraceCsv.parse(
      "q.csv",
      s"$header,\"two\nlines\"\n${rowA.mkString(",")},1\n${rowB.mkString(",")},2\n",
      columns
    )
    assert(multi.rows.map(_._1) == Seq(3, 4))
    refused("q.csv:4:", "column 'two?lines'", "not a number") {
      TraceCsv.parse(
        "q.csv",
        s"$header,\"two\nlines\"\n${rowA.mkString(",")},1\n${rowB.mkString(",")},x\n",
        columns
      )
    }
  }

  it should "read CRLF and lone-CR line endings like LF" in {
    sameAsPlain(TraceCsv.parse("crlf.csv", plainText.replace("\n", "\r\n"), columns))
    sameAsPlain(TraceCsv.parse("cr.csv", plainText.replace("\n", "\r"), columns))
    assert(TraceCsv.parse("cr.csv", plainText.replace("\n", "\r"), columns).rows.map(_._1) == Seq(3, 4))
    assert(TraceCsv.parse("crlf.csv", plainText.replace("\n", "\r\n"), columns).rows.map(_._1) == Seq(3, 4))
    refused("crlf.csv:4:", "column 'd3'", "not a number") {
      TraceCsv.parse("crlf.csv", plainText.replace("\n", "\r\n").replace("0.5,-1", "0.5,?"), columns)
    }
  }

  it should "decompress a .csv.gz file on the fly" in {
    val f = tempFile(".csv.gz", gzip(utf8(plainText.replace("\n", "\r\n"))))
    sameAsPlain(TraceCsv.read(f, columns))
    val bom = tempFile(".csv.gz", gzip(Array(0xef, 0xbb, 0xbf).map(_.toByte) ++ utf8(plainText)))
    sameAsPlain(TraceCsv.read(bom, columns))
  }

  it should "refuse a corrupt or truncated gzip file with one line" in {
    val notGzip = tempFile(".csv.gz", utf8(plainText))
    refused(notGzip.toString, "not a valid gzip file")(TraceCsv.read(notGzip, columns))
    val whole = gzip(utf8(plainText * 50))
    val truncated = tempFile(".csv.gz", whole.take(whole.length / 2))
    refused(truncated.toString, "not a valid gzip file")(TraceCsv.read(truncated, columns))
    val flipped = whole.clone()
    flipped(whole.length / 2) = (flipped(whole.length / 2) ^ 0x55).toByte
    val corrupt = tempFile(".csv.gz", flipped)
    refused(corrupt.toString, "not a valid gzip file")(TraceCsv.read(corrupt, columns))
  }

  it should "refuse an unterminated quote and text after a closing quote with file:line and column" in {
    refused("u.csv:3:", "column 'd1'", "unterminated quoted field", "line 3") {
      TraceCsv.parse(
        "u.csv",
        s"$header\n${rowA.mkString(",")}\n0.1,0.2,0.3,\"1,-1,0.5,2,3,-4\n${rowB.mkString(",")}\n",
        columns
      )
    }
    refused("u.csv:1:", "header field 2", "unterminated quoted field") {
      TraceCsv.parse("u.csv", "t1,\"t2,t3\n", columns)
    }
    refused("u.csv:2:", "column 't2'", "after a closing quote") {
      TraceCsv.parse("u.csv", s"$header\n0.1,\"0.2\"x,0.3,1,-1,0.5,2,3,-4\n", columns)
    }
  }

  it should "keep the existing errors: missing column, wrong count, not a number, each one line" in {
    refused("m.csv:1:", "missing column(s) 'd1'")(
      TraceCsv.parse("m.csv", s"${header.replace("d1", "v1")}\n${rowA.mkString(",")}\n", columns)
    )
    refused("m.csv:2:", "2 values")(TraceCsv.parse("m.csv", s"$header\n0.1,0.2\n", columns))
    refused("m.csv:2:", "column 'dd2'", "not a finite number")(
      TraceCsv.parse("m.csv", s"$header\n0.1,0.2,0.3,1,-1,0.5,2,NaN,-4\n", columns)
    )
    refused("m.csv", "no data rows")(TraceCsv.parse("m.csv", s"# c\n$header\r\n\r\n", columns))
    refused("m.csv", "empty")(TraceCsv.parse("m.csv", "\uFEFF# only a comment\n", columns))
  }

  it should "refuse columns of joints the robot does not have (q3 beside a 2-joint arm's q1..qdd2), naming file and column" in {
    val arm = Seq("q1", "q2", "qd1", "qd2", "qdd1", "qdd2")
    val row = Seq.fill(7)("0").mkString(",")
    Seq("q3", "qd4", "qdd3", "q0").foreach { extra =>
      val t = TraceCsv.parse("two.csv", s"# c\n${arm.mkString(",")},$extra\n$row\n", arm)
      refused("two.csv:2:", s"column '$extra'", "the robot has 2 joints", "q1..q2, qd1..qd2, qdd1..qdd2")(
        TraceCsv.checkJointColumns(t, arm)
      )
    }
    // Other columns (a time stamp, recorded torques) are still ignored.
    val t = TraceCsv.parse("two.csv", s"time,${arm.mkString(",")},tau1\n$row,0\n", arm)
    TraceCsv.checkJointColumns(t, arm)
    // The joint-3 closed form reads three joints: t4 is not one of them.
    refused("j3.csv:1:", "column 't4'", "3 joints")(
      TraceCsv.checkJointColumns(
        TraceCsv.parse("j3.csv", s"$header,t4\n${rowA.mkString(",")},0\n", columns),
        columns
      )
    )
  }

  it should "quote a huge header in an error by a short prefix and its length" in {
    val names = Iterator.from(1).map(i => s"column_number_$i").take(20000).mkString(",") // about 340 kB
    refused("big.csv:1:", "missing column(s) 't1'", "... (", "characters)") {
      val e = intercept[InputError](TraceCsv.parse("big.csv", s"$names\n1\n", columns))
      assert(e.getMessage.length < 400, s"${e.getMessage.length} characters")
      throw e
    }
  }

  it should "refuse a line longer than its limit (from the column count) with file and line, before reading it" in {
    val limit = RecordLimit.rows(columns.size)
    assert(limit.chars == 4096 + 1024 * columns.size)
    val long = "1" * (limit.chars + 1)
    // A data line of one enormous number, one of many cells, and one quoted cell spanning lines.
    Seq(long, Seq.fill(columns.size)("1" * 1500).mkString(","), "\"" + "1\n" * limit.chars + "\"").foreach {
      row =>
        refused("long.csv:3:", "line longer than 13312 characters", "9 columns")(
          TraceCsv.parse("long.csv", s"$header\n${rowA.mkString(",")}\n$row\n", columns)
        )
    }
    // A line at the limit is read (blanks around numbers are allowed).
    val padded = rowA.map(_ + " " * 1000).mkString(",")
    assert(TraceCsv.parse("ok.csv", s"$header\n$padded\n", columns).size == 1)
    // The header line has its own limit; a small one (as the file's would be for a huge header) shows it.
    refused("h.csv:2:", "line longer than 20 characters", "header limit")(
      TraceCsv.parse("h.csv", s"# c\n$header\n", columns, 1 << 22, RecordLimit(20, "the header limit"))
    )
    // The reader stops at the limit: a line ten times the limit is refused as soon as the limit is passed.
    val reader = new CsvRecordReader("r.csv", "x" * 1000 + "\n", limit = RecordLimit(100, "test"))
    refused("r.csv:1:", "longer than 100")(reader.next(i => s"field $i"))
  }

  /** Cells as files hold them: every rendering of doubles, integers, and near misses of the grammar. */
  private def fuzzCell(rng: Random): String = {
    def digits(n: Int) = Seq.fill(n)(rng.nextInt(10)).mkString
    val x = (rng.nextDouble() * 2 - 1) * math.pow(10, rng.nextInt(40) - 20)
    rng.nextInt(12) match {
      case 0 => x.toString
      case 1 => s"%.${rng.nextInt(20)}f".format(x)
      case 2 => s"%.${rng.nextInt(20)}e".format(x).replace("e", if (rng.nextBoolean()) "e" else "E")
      case 3 => s"${if (rng.nextBoolean()) "-" else "+"}${digits(rng.nextInt(25))}.${digits(rng.nextInt(25))}"
      case 4 =>
        s"${digits(1 + rng.nextInt(20))}e${if (rng.nextBoolean()) "-" else ""}${digits(1 + rng.nextInt(4))}"
      case 5 => s".${digits(1 + rng.nextInt(20))}"
      case 6 => s"${digits(1 + rng.nextInt(3))}."
      case 7 =>
        Seq
          .fill(1 + rng.nextInt(8))("0123456789.+-eE xd".charAt(rng.nextInt(18)))
          .mkString // mostly not numbers
      case 8 => s"${" " * rng.nextInt(3)}${rng.nextLong()}${"\t" * rng.nextInt(2)}"
      case 9 =>
        Seq(
          "1e400",
          "-1e400",
          "1e-400",
          "0",
          "-0",
          "-0.0",
          "4.9e-324",
          "1.7976931348623157e308",
          "9007199254740993",
          "NaN",
          "inf",
          ""
        ).apply(rng.nextInt(12))
      case 10 => s"${digits(1 + rng.nextInt(18))}e${rng.nextInt(60) - 30}"
      case _  => java.lang.Double.toString(java.lang.Double.longBitsToDouble(rng.nextLong()))
    }
  }

  it should "read a cell's number straight from the text exactly as the general parser does (seeded fuzz corpus)" in {
    val rng = new Random(Seeds("decimal-cell", 71L))
    val cells = Seq.fill(200000)(fuzzCell(rng))
    val wrong = cells.filter { c =>
      val fast = DecimalCell.parse(c, 0, c.length)
      TraceCsv.parseNumber(c.trim) match {
        case Some(v) => java.lang.Double.doubleToRawLongBits(fast) != java.lang.Double.doubleToRawLongBits(v)
        case None    => !fast.isNaN
      }
    }
    assert(
      wrong.isEmpty,
      s"fast and general parse differ on ${wrong.take(5).map("'" + _ + "'").mkString(", ")}"
    )
    assert(
      cells.count(c => TraceCsv.parseNumber(c.trim).isDefined) > cells.size / 2,
      "the corpus is mostly numbers"
    )
  }

  it should "read every double as Double.toString and %.17g write it, bit for bit (seeded)" in {
    val rng = new Random(Seeds("decimal-cell-doubles", 73L))
    val xs = Seq
      .fill(300000)(java.lang.Double.longBitsToDouble(rng.nextLong()))
      .filter(x => !x.isNaN && !x.isInfinite) ++
      Seq.fill(100000)((rng.nextDouble() * 2 - 1) * math.pow(10, rng.nextInt(10) - 5))
    val wrong = xs.flatMap(x => Seq(x.toString, "%.17g".format(x), "%.16e".format(x))).filter { c =>
      java.lang.Double.doubleToRawLongBits(DecimalCell.parse(c, 0, c.length)) != java.lang.Double
        .doubleToRawLongBits(c.toDouble)
    }
    assert(wrong.isEmpty, s"differs on ${wrong.take(5).mkString(", ")}")
  }

  it should "read plain rows (fast path) and quoted rows (general path) of a fuzzed file alike, errors included" in {
    val rng = new Random(Seeds("trace-csv-fast-rows", 72L))
    (0 until 200).foreach { round =>
      val rows = Seq.fill(1 + rng.nextInt(30))(
        Seq
          .fill(columns.size)(fuzzCell(rng))
          .map(c => if (rng.nextInt(4) == 0) c else (rng.nextDouble() * 10).toString)
      )
      val ends = Seq("\n", "\r\n", "\r")(rng.nextInt(3))
      def text(quote: Boolean) =
        (header +: rows.map(_.map(c => if (quote) "\"" + c + "\"" else c).mkString(",")))
          .mkString(ends) + (if (rng.nextBoolean()) ends else "")
      def outcome(t: String) = scala.util
        .Try(TraceCsv.parse(s"f$round.csv", t, columns))
        .toEither
        .left
        .map(_.getMessage)
        .map(t => t.rows.map { case (line, v) => line -> v.map(java.lang.Double.doubleToRawLongBits) })
      val plainRead = outcome(text(quote = false))
      assert(plainRead == outcome(text(quote = true)), s"round $round: ${rows.take(3)}")
      // Read in segments of a few characters (in parallel): the same rows, lines, comments and first error.
      val withComments = text(quote = false)
        .replace(s"${ends}${rows.head.head}", s"${ends}# note${ends}${ends}${rows.head.head}")
      def segmented(chars: Int) = scala.util
        .Try(TraceCsv.parse(s"f$round.csv", withComments, columns, chars))
        .toEither
        .left
        .map(_.getMessage)
        .map(t =>
          (t.comments, t.rows.map { case (line, v) => line -> v.map(java.lang.Double.doubleToRawLongBits) })
        )
      val whole = segmented(Int.MaxValue)
      Seq(1, 7, 50, 300).foreach(chars =>
        assert(segmented(chars) == whole, s"round $round, segments of $chars characters")
      )
    }
  }
}
