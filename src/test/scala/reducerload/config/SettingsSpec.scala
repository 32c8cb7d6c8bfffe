package reducerload.config

import com.typesafe.config.ConfigFactory
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.app.Main
import reducerload.cordic.CordicParams
import reducerload.load.LoadModel
import reducerload.robot.RobotParams
import reducerload.util.InputError

import java.nio.file.{Files, Paths}

class SettingsSpec extends AnyFlatSpec {
  behavior of "Settings"

  private def parse(text: String, source: String = "test.conf") =
    Settings.toParams(ConfigFactory.parseString(text), source)
  private val defaultText = Settings.render(LoadParams.default, Nil)

  it should "ship preset files that are exactly the presets in the code" in {
    LoadParams.allPresets.foreach { case (name, p) =>
      val file = Paths.get("configs", s"$name.conf")
      val text = new String(Files.readAllBytes(file), "UTF-8")
      assert(
        text == Settings.render(p, Main.presetHeader(name)),
        s"$file is stale: regenerate it as its header says"
      )
      assert(parse(text, file.toString) == p)
    }
  }

  it should "round-trip parameters through a configuration file" in {
    val p = LoadParams(
      robot = RobotParams(
        m3 = 7.5,
        l1 = 0.5,
        l2 = 0.25,
        l3 = 0.45,
        g = 0.0,
        maxVelocity = Seq(1.0, 2.0, 3.5),
        maxAcceleration = Seq(4.0, 5.0, 6.0)
      ),
      model = LoadModel.PaperEq6,
      cordic = CordicParams(
        angleBits = 20,
        outputBits = 18,
        iterations = 15,
        guardBits = 3,
        angleGuardBits = 4,
        iterationsPerStage = 2
      ),
      datapath = DatapathParams(
        velocityFracBits = 14,
        accelerationFracBits = 15,
        constantFracBits = 18,
        internalFracBits = 16,
        outputFracBits = 12,
        multiplierLatency = 2
      )
    )
    assert(parse(Settings.render(p, Seq("x"))) == p)
  }

  it should "name the key and the file for unknown keys, wrong types, missing keys and bad values" in {
    def refused(text: String, words: String*): Unit = {
      val e = intercept[InputError](parse(text))
      assert(!e.getMessage.contains("\n"), s"error spans lines: ${e.getMessage}")
      (words :+ "test.conf").foreach(w =>
        assert(e.getMessage.contains(w), s"'${e.getMessage}' does not mention '$w'")
      )
    }
    refused(defaultText + "\nrobot.mass = 3\n", "unknown key 'robot.mass'")
    refused(
      defaultText + "\ncordic.iteration = 3\n",
      "unknown key 'cordic.iteration'",
      "did you mean 'cordic.iterations'"
    )
    refused(defaultText + "\nrobot.m3 = heavy\n", "robot.m3", "a number")
    refused(defaultText + "\ncordic.iterations = 12.5\n", "cordic.iterations", "an integer")
    refused(defaultText + "\nmodel = newton\n", "model", "exact, paper")
    refused(defaultText + "\nrobot.max-velocity = [1, 2]\n", "robot.max-velocity", "3 numbers")
    refused(defaultText.linesIterator.filterNot(_.contains("m3 =")).mkString("\n"), "missing key 'robot.m3'")
    refused(defaultText + "\nrobot.m3 = -1\n", "m3", "must be")
    refused(defaultText + "\ncordic.iterations = 0\n", "iterations")
    refused(defaultText + "\nrobot.units = imperial\n", "unknown key 'robot.units'")
  }
}

class ReadmeSpec extends AnyFlatSpec {
  behavior of "README.md"

  private val readme = new String(Files.readAllBytes(Paths.get("README.md")), "UTF-8")

  it should "carry the settings table exactly as the code defines it" in {
    assert(
      readme.contains(Settings.markdownTable),
      "README settings table is stale: paste Settings.markdownTable"
    )
  }

  it should "carry the preset table exactly as the presets measure" in {
    assert(
      readme.contains(reducerload.app.PresetsTable.markdown),
      "README preset table is stale: paste ./sbt --error \"run presets-table\""
    )
  }

  it should "show the two commands and the simulator switch" in {
    Seq("./sbt run", "./sbt test", "REDUCERLOAD_SIM").foreach(w =>
      assert(readme.contains(w), s"README lacks $w")
    )
  }
}

class SweepDocsSpec extends AnyFlatSpec {
  behavior of "the README benchmark section"

  it should "show the table that run sweep wrote into docs/sweep" in {
    val readme = new String(Files.readAllBytes(Paths.get("README.md")), "UTF-8")
    val table = new String(Files.readAllBytes(Paths.get("docs", "sweep", "sweep.md")), "UTF-8").linesIterator
      .filter(_.startsWith("|"))
      .toSeq
    assert(table.size > 2)
    table.foreach(row => assert(readme.contains(row), s"README lacks the sweep row: $row"))
    Seq("error_vs_les.png", "memory_vs_precision.png").foreach(f =>
      assert(Files.exists(Paths.get("docs", "sweep", f)), s"docs/sweep/$f missing")
    )
  }

  it should "show the arm table that run sweep --arms wrote into docs/sweep" in {
    val readme = new String(Files.readAllBytes(Paths.get("README.md")), "UTF-8")
    val table = new String(Files.readAllBytes(Paths.get("docs", "sweep", "arms.md")), "UTF-8").linesIterator
      .filter(_.startsWith("|"))
      .toSeq
    assert(table.size > 2)
    table.foreach(row => assert(readme.contains(row), s"README lacks the arm sweep row: $row"))
    assert(Files.exists(Paths.get("docs", "sweep", "arms_pareto.png")), "docs/sweep/arms_pareto.png missing")
  }

  it should "quote the sweep's own figures in the preset comparison beside the paper" in {
    val readme = new String(Files.readAllBytes(Paths.get("README.md")), "UTF-8").linesIterator.toSeq
    val csv = new String(Files.readAllBytes(Paths.get("docs", "sweep", "sweep.csv")), "UTF-8").linesIterator
      .map(_.split(",", -1).toSeq)
      .toSeq
    val column = csv.head.zipWithIndex.toMap
    val sweep = csv.tail.map(r => r(column("config")) -> r).toMap
    val table = readme
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
          s"README $name: $key shown as '$cell', sweep.csv has $measured"
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
}
