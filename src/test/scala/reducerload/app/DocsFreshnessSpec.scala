package reducerload.app

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.config.LoadParams
import reducerload.monitor.MonitorDoc
import reducerload.testutil.Scratch

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path, Paths}
import scala.jdk.CollectionConverters._

/**
 * Generated documentation is checked by regenerating it and comparing it whole, not by looking for
 * substrings: a block between `<!-- generated: KEY ... -->` and `<!-- end generated -->` in the README or
 * docs/ must equal what the code behind KEY produces now, and docs/sweep/NAME.md must equal the markdown the
 * sweep code makes from the committed CSV.
 */
class DocsFreshnessSpec extends AnyFlatSpec {
  behavior of "the README and docs/"

  private def read(p: Path): String = new String(Files.readAllBytes(p), StandardCharsets.UTF_8)
  private val sweepDir = Paths.get("docs", "sweep")
  private val readme = Paths.get("README.md")

  /** docs/sweep/NAME.md as the sweep code writes it from the committed NAME.csv. */
  private def sweepMarkdown(name: String): String = {
    val cells = Sweep.cellsOf(read(sweepDir.resolve(s"$name.csv")))
    val fmaxColumn = cells.head.indexOf("fmax_ecp5_mhz")
    assert(fmaxColumn >= 0, s"docs/sweep/$name.csv has no fmax_ecp5_mhz column")
    // The proxy's column is filled exactly when the sweep ran with --fmax.
    val fmax = cells.tail.forall(_(fmaxColumn).nonEmpty)
    val out = Some(sweepDir.toString)
    name match {
      case "sweep" => Sweep.markdown(cells, fmax, out)
      case "arms" =>
        ArmSweep.markdown(cells, fmax, Sweep.command(arms = true, out, fmax), ArmSweep.cpuAnchors(sweepDir))
    }
  }

  private def linesOf(text: String): Seq[String] = text.linesIterator.toSeq

  /** What each generated block holds, by the KEY its marker names (lazily: the preset table measures). */
  private lazy val generators: Map[String, () => Seq[String]] = Map(
    "./sbt --error \"run presets-table\"" -> (() => linesOf(PresetsTable.markdown)),
    "docs/sweep/sweep.md" -> (() => linesOf(sweepMarkdown("sweep"))),
    "docs/sweep/arms.md" -> (() => linesOf(sweepMarkdown("arms"))),
    "docs/sweep/arms.csv docs/sweep/cpu.csv" -> (() =>
      ArmSweep.anchors(
        Sweep.cellsOf(read(sweepDir.resolve("arms.csv"))),
        ArmSweep.cpuAnchors(sweepDir).get,
        detail = false
      )
    ),
    "./sbt --error \"runMain reducerload.monitor.MonitorDoc\"" -> (() =>
      linesOf(MonitorDoc.text).drop(1).dropRight(1)
    ),
    RegisterMapDoc.key -> (() => RegisterMapDoc.lines)
  )

  private val begin = "<!-- generated: "
  private val end = "<!-- end generated -->"

  /** The README and every markdown file of docs/ but the settings reference, which its own test checks. */
  private def documents: Seq[Path] =
    readme +: Files
      .list(Paths.get("docs"))
      .iterator()
      .asScala
      .filter(p => p.toString.endsWith(".md") && p.getFileName.toString != "configuration.md")
      .toSeq
      .sorted

  /** (file, key, lines between the markers) of every generated block. */
  private def blocks(file: Path): Seq[(String, Seq[String])] = {
    def from(lines: List[String]): List[(String, Seq[String])] =
      lines.dropWhile(!_.startsWith(begin)) match {
        case Nil => Nil
        case marker :: rest =>
          val key = marker.stripPrefix(begin).stripSuffix("-->").trim.split(" \\(").head.trim
          val (body, after) = rest.span(_ != end)
          assert(after.nonEmpty, s"$file: the block '$key' has no '$end'")
          (key -> body) :: from(after.drop(1))
      }
    from(linesOf(read(file)).toList)
  }

  it should "carry every generated block exactly as the code generates it now" in {
    val found = documents.flatMap(f => blocks(f).map { case (key, body) => (f, key, body) })
    // Every stale block is named at once: regenerating one often means regenerating several.
    val stale = found.flatMap { case (file, key, body) =>
      val expected = generators.getOrElse(key, fail(s"$file: no generator known for the block '$key'"))()
      val firstDifference = body.zipAll(expected, "", "").indexWhere { case (a, b) => a != b }
      if (firstDifference < 0) None
      else Some(s"$file: the block '$key' is stale from its line ${firstDifference + 1}: regenerate it")
    }
    assert(stale.isEmpty, stale.mkString("; "))
    generators.keys.foreach(key =>
      assert(found.exists(_._2 == key), s"no document carries the generated block '$key'")
    )
  }

  it should "hold in docs/sweep the markdown the sweep code writes from the committed CSV" in {
    Seq("sweep", "arms").foreach { name =>
      assert(
        read(sweepDir.resolve(s"$name.md")) == sweepMarkdown(name),
        s"docs/sweep/$name.md differs from what the sweep writes from docs/sweep/$name.csv"
      )
    }
    Seq("error_vs_les.png", "memory_vs_precision.png", "arms_pareto.png").foreach(f =>
      assert(Files.exists(sweepDir.resolve(f)), s"docs/sweep/$f missing")
    )
  }

  it should "quote the sweep's own figures in the preset comparison beside the paper" in {
    val doc = linesOf(read(Paths.get("docs", "benchmarks.md")))
    val csv = Sweep.cellsOf(read(sweepDir.resolve("sweep.csv")))
    val column = csv.head.zipWithIndex.toMap
    val sweep = csv.tail.map(r => r(column("config")) -> r).toMap
    val table = doc
      .dropWhile(!_.startsWith("| design | max error, golden traces |"))
      .drop(2)
      .takeWhile(_.startsWith("|"))
    val presetRows = table.filter(_.startsWith("| `"))
    assert(
      presetRows.size == LoadParams.presets.size,
      s"the comparison lists ${presetRows.size} presets, the code has ${LoadParams.presets.size}"
    )
    def number(cell: String): Double =
      cell.trim.takeWhile(c => c.isDigit || ",.e-".contains(c)).replace(",", "").toDouble
    presetRows.foreach { line =>
      val cells = line.split('|').map(_.trim).drop(1).toSeq
      val name = cells.head.stripPrefix("`").takeWhile(_ != '`')
      val row = sweep.getOrElse(s"preset-$name", fail(s"sweep.csv has no preset-$name"))
      def agrees(cell: String, key: String, relTol: Double): Unit = {
        val (shown, measured) = (number(cell), row(column(key)).toDouble)
        assert(
          math.abs(shown - measured) <= relTol * math.abs(measured),
          s"docs/benchmarks.md $name: $key shown as '$cell', sweep.csv has $measured"
        )
      }
      agrees(cells(1), "max_error_nm", 0.05)
      agrees(cells(2), "est_les", 0)
      agrees(cells(3), "registers", 0)
      agrees(cells(4), "mult18x18", 0)
      agrees(cells(5), "memory_bits", 0)
      agrees(cells(6), "fmax_ecp5_mhz", 0.001)
      agrees(cells(7), "results_per_s", 0.01)
      agrees(cells(8), "latency_cycles", 0)
    }
  }

  it should "refuse a CPU-anchor file with a missing column or a bad number, naming the file and line" in {
    val dir = Scratch.dir("cpu-anchors-")
    val good = read(sweepDir.resolve("cpu.csv"))
    def refused(text: String, expected: String): Unit = {
      Files.write(dir.resolve("cpu.csv"), text.getBytes(StandardCharsets.UTF_8))
      val e = intercept[reducerload.util.InputError](ArmSweep.cpuAnchors(dir))
      assert(
        e.getMessage.contains(dir.resolve("cpu.csv").toString) && e.getMessage.contains(expected),
        e.getMessage
      )
    }
    refused(good.replace("calls_per_s", "calls"), "line 1: no column 'calls_per_s'")
    val lines = good.linesIterator.toSeq
    val cells = lines(2).split(",", -1)
    cells(lines.head.split(",").indexOf("us_per_call")) = "fast"
    refused(
      (lines.take(2) :+ cells.mkString(",")).mkString("\n"),
      "line 3: us_per_call 'fast' is not a positive number"
    )
    refused((lines.take(2) :+ (lines(2) + ",x")).mkString("\n"), "line 3: 9 cells, the header has 8")
    Files.write(dir.resolve("cpu.csv"), good.getBytes(StandardCharsets.UTF_8))
    assert(ArmSweep.cpuAnchors(dir).get.size == lines.size)
  }

  it should "keep the README short and every link inside the repository and alive" in {
    val size = Files.size(readme)
    assert(size < 20000, s"README.md is $size bytes; keep it under 20 KB (details belong in docs/)")
    val markdown = readme +: (documents.tail ++ Seq(
      Paths.get("golden", "README.md"),
      Paths.get("quartus", "README.md"),
      Paths.get("tools", "bench", "README.md"),
      Paths.get("tools", "estimate", "README.md")
    ))
    val link = """\]\(([^)\s#]*)(#[^)\s]*)?\)""".r
    markdown.foreach { file =>
      val text = read(file)
      assert(!text.contains("../shared"), s"$file links outside the repository (../shared)")
      link.findAllMatchIn(text).map(_.group(1)).filter(t => t.nonEmpty && !t.contains("://")).foreach {
        target =>
          val resolved = Option(file.getParent).getOrElse(Paths.get("")).resolve(target).normalize
          assert(Files.exists(resolved), s"$file links to $target, which does not exist")
      }
    }
  }
}
