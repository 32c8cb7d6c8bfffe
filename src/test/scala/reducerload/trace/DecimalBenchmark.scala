package reducerload.trace

import ch.randelshofer.fastdoubleparser.JavaDoubleParser

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Paths}
import scala.collection.mutable.ArrayBuffer

/**
 * Decimal cells to doubles on a trajectory CSV: every data cell of FILE parsed by [[DecimalCell]] (the
 * reader's: TraceCsv's grammar, then FastDoubleParser), by FastDoubleParser alone and by the JDK's
 * `Double.parseDouble` (best of ROUNDS, ns per cell), the results compared bit for bit, and `TraceCsv.read`
 * of the whole file for scale: ./sbt "Test/runMain reducerload.trace.DecimalBenchmark FILE [ROUNDS]" e.g. on
 * a million rows from ./sbt "run trajectory --output /tmp/traj.csv".
 */
object DecimalBenchmark {
  def main(args: Array[String]): Unit = {
    require(args.nonEmpty, "usage: DecimalBenchmark FILE [ROUNDS]")
    val rounds = args.lift(1).map(_.toInt).getOrElse(5)
    val text = new String(Files.readAllBytes(Paths.get(args(0))), StandardCharsets.ISO_8859_1)
    val (starts, ends) = (new ArrayBuffer[Int], new ArrayBuffer[Int])
    var header = true
    text.linesWithSeparators.foldLeft(0) { (at, line) =>
      val body = line.stripLineEnd
      if (body.nonEmpty && !body.startsWith("#")) {
        if (header) header = false
        else {
          var from = at
          body.split(",", -1).foreach { cell =>
            starts += from; ends += from + cell.length; from += cell.length + 1
          }
        }
      }
      at + line.length
    }
    val n = starts.size
    val (s, e) = (starts.toArray, ends.toArray)
    def measure(parse: (Int, Int) => Double): (Double, Array[Long]) = {
      val bits = new Array[Long](n)
      val best = (1 to rounds).map { _ =>
        val t0 = System.nanoTime()
        var i = 0
        while (i < n) { bits(i) = java.lang.Double.doubleToRawLongBits(parse(s(i), e(i))); i += 1 }
        (System.nanoTime() - t0).toDouble / n
      }.min
      (best, bits)
    }
    val parsers = Seq[(String, (Int, Int) => Double)](
      "DecimalCell (its grammar)" -> ((a, b) => DecimalCell.parse(text, a, b)),
      "FastDoubleParser 2.0.1" -> ((a, b) => JavaDoubleParser.parseDouble(text, a, b - a)),
      "Double.parseDouble (JDK)" -> ((a, b) => java.lang.Double.parseDouble(text.substring(a, b)))
    )
    val results = parsers.map { case (name, f) => (name, measure(f)) }
    val reference = results.last._2._2
    println(s"$n cells of ${args(0)}, best of $rounds rounds, Java ${System.getProperty("java.version")}")
    println(f"${"parser"}%-28s ${"ns/cell"}%8s  cells equal to the JDK's (bits)")
    results.foreach { case (name, (ns, bits)) =>
      val same = bits.indices.count(i => bits(i) == reference(i))
      println(f"$name%-28s $ns%8.1f  $same%d/$n")
    }
    val read = (1 to rounds).map { _ =>
      val t0 = System.nanoTime()
      TraceCsv.read(Paths.get(args(0)), Nil)
      (System.nanoTime() - t0) / 1e9
    }.min
    println(f"TraceCsv.read of the whole file (parallel segments): $read%.3f s")
    // One thread each: CsvRecordReader's row path against commons-csv with the same cell parser.
    val headerEnd = text.indexOf('\n') // a file without comment lines, as `run trajectory` writes
    val body = text.substring(headerEnd + 1)
    val width = text.substring(0, headerEnd).split(",").length
    val own = (1 to rounds).map { _ =>
      val t0 = System.nanoTime()
      val reader = new CsvRecordReader("f", body)
      val row = new Array[Double](width)
      var rows = 0
      while (reader.nextNumbers(row, 0, width) > 0) rows += 1
      require(rows > 0)
      (System.nanoTime() - t0) / 1e9
    }.min
    val commons = (1 to rounds).map { _ =>
      val t0 = System.nanoTime()
      val format = org.apache.commons.csv.CSVFormat.DEFAULT.builder
        .setCommentMarker('#')
        .setIgnoreSurroundingSpaces(true)
        .build()
      val parser = format.parse(new java.io.StringReader(body))
      val row = new Array[Double](width)
      parser.forEach { r =>
        var c = 0
        while (c < width) { val v = r.get(c); row(c) = DecimalCell.parse(v, 0, v.length); c += 1 }
      }
      (System.nanoTime() - t0) / 1e9
    }.min
    println(f"rows, one thread: CsvRecordReader $own%.3f s, commons-csv 1.12.0 $commons%.3f s")
  }
}
