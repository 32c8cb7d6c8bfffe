package reducerload.config

import reducerload.testutil.CompiledParams
import com.typesafe.config.ConfigFactory
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.app.Cli
import reducerload.compiler.Compiler
import reducerload.load.LoadModel
import reducerload.monitor.MonitorConfig
import reducerload.util.InputError

/** The `monitor.*` keys: defaults, round trip, derived values, and one-line refusals naming the key. */
class MonitorSettingsSpec extends AnyFlatSpec {
  behavior of "the monitor settings"

  private def parse(text: String) = Settings.toParams(ConfigFactory.parseString(text), "test.conf")
  private val defaultText = Settings.render(LoadParams.default, Nil)
  private val ur5 =
    Seq("--robot", "golden/robots/ur5_robot.urdf", "--tip", "tool0", "--max-acceleration", "10")
  private def params(args: String*) = Cli.parse("emit", args, Nil).params

  it should "default to off, p = 3, URDF limits with T_M = 1.5 x effort, i = 100, 1 ms, 16 auto bins, no rating" in {
    val s = LoadParams.default.monitor
    assert(s == MonitorSettings())
    assert(
      !s.enabled && s.exponent == Seq(
        3.0
      ) && s.repeatedPeakNm.isEmpty && s.momentaryPeakNm.isEmpty && s.momentaryPeakFactor == 1.5
    )
    assert(
      s.gearRatio == Seq(100.0) && s.samplePeriodS == 1e-3 && s.histogramBins == Seq(
        16
      ) && s.histogramBinWidthNm.isEmpty
    )
    assert(s.ratedTorqueNm.isEmpty && s.ratedInputSpeedRpm == 2000.0 && s.ratedLifeHours == 35000.0)
    Seq(
      "enabled = false",
      "exponent = 3.0",
      "repeated-peak = urdf",
      "momentary-peak = urdf",
      "momentary-peak-factor = 1.5",
      "gear-ratio = 100.0",
      "sample-period = 0.001",
      "histogram-bins = 16",
      "histogram-bin-width = auto",
      "rated-torque = none"
    )
      .foreach(line => assert(defaultText.contains(line), s"the rendered defaults lack '$line'"))
    Seq("monitor.enabled", "monitor.exponent", "monitor.histogram-bin-width").foreach(k =>
      assert(reducerload.app.Main.help.contains(s"--$k"), s"--help lacks $k")
    )
  }

  it should "round-trip per-joint values and keywords through a configuration file" in {
    val p = LoadParams(
      model = LoadModel.Rnea,
      monitor = MonitorSettings(
        enabled = true,
        exponent = Seq(3.0, 10.0 / 3, 1.5),
        repeatedPeakNm = Seq(20.0),
        momentaryPeakNm = Seq(90.0, 50.0, 30.5),
        gearRatio = Seq(101.0, 81.0, 51.0),
        samplePeriodS = 2.5e-4,
        histogramBins = Seq(8, 12, 16),
        histogramBinWidthNm = Seq(10.0),
        ratedTorqueNm = Seq(40.0, 20.0, 10.0)
      )
    )
    assert(parse(Settings.render(p, Nil)) == p)
  }

  it should "derive the UR5's limits from <limit effort> and auto bin widths from the torque range" in {
    val p = params(ur5 ++ Seq("--monitor.enabled", "true", "--monitor.momentary-peak-factor", "2"): _*)
    val arm = Compiler.arm(p)
    val m = MonitorConfig(arm, p.monitor)
    assert(m.repeatedPeakNm == arm.chain.joints.map(_.effortLimit.get))
    assert(m.momentaryPeakNm == arm.chain.joints.map(_.effortLimit.get * 2))
    m.histogramBinWidthNm.indices.foreach { j =>
      val range = arm.analysis.outputs(j).range.maxAbs
      assert(
        m.histogramBinWidthNm(j) * m.histogramBins(j) >= range && m.histogramBinWidthNm(j) * m.histogramBins(
          j
        ) <= range * 1.01
      )
    }
  }

  it should "refuse bad values with one line naming the key" in {
    def refused(text: String, words: String*): Unit = {
      // Settings are checked when read; the monitor against its arm when the design compiles.
      val e = intercept[InputError](Compiler.compile(parse(defaultText + "\n" + text + "\n"), "test.conf"))
      assert(!e.getMessage.contains("\n"), s"error spans lines: ${e.getMessage}")
      (words :+ "test.conf").foreach(w =>
        assert(e.getMessage.contains(w), s"'${e.getMessage}' does not mention '$w'")
      )
    }
    val rnea = "model = rnea\nmonitor.enabled = true\nmonitor.repeated-peak = 60\nmonitor.momentary-peak = 90"
    refused("monitor.enabled = yes", "monitor.enabled", "true or false")
    refused("monitor.exponent = 0.5", "monitor.exponent", "[1, 10]")
    refused("monitor.exponent = 11", "monitor.exponent")
    refused("monitor.exponent = urdf", "monitor.exponent", "a number")
    refused("monitor.repeated-peak = -3", "monitor.repeated-peak", "positive")
    refused("monitor.momentary-peak = auto", "monitor.momentary-peak", "urdf")
    refused("monitor.momentary-peak-factor = 1", "monitor.momentary-peak-factor")
    refused("monitor.gear-ratio = 0", "monitor.gear-ratio")
    refused("monitor.sample-period = 0", "monitor.sample-period")
    refused("monitor.histogram-bins = 0", "monitor.histogram-bins", "1..256")
    refused("monitor.histogram-bins = 2.5", "monitor.histogram-bins", "an integer")
    refused("monitor.histogram-bin-width = -1", "monitor.histogram-bin-width")
    refused("monitor.rated-torque = some", "monitor.rated-torque", "none")
    refused("monitor.rated-life = 0", "monitor.rated-life")
    refused("monitor.enabled = true", "monitor.enabled", "model rnea")
    // planar3 has no URDF: its limits must be given when the monitor is on.
    refused("model = rnea\nmonitor.enabled = true", "monitor.repeated-peak", "planar3", "<limit effort>")
    refused(
      "model = rnea\nmonitor.enabled = true\nmonitor.repeated-peak = 60",
      "monitor.momentary-peak",
      "planar3"
    )
    refused(
      rnea + "\nmonitor.momentary-peak = 50",
      "monitor.momentary-peak",
      "must exceed monitor.repeated-peak"
    )
    refused(rnea + "\nmonitor.gear-ratio = [100, 100]", "monitor.gear-ratio", "2 values", "3 joints")
    refused(rnea + "\nmonitor.histogram-bin-width = 1e-9", "monitor.histogram-bin-width", "LSB")
    refused(rnea + "\nmonitor.momentary-peak = 1e12", "monitor.momentary-peak", "bit")
    assert(parse(defaultText + "\n" + rnea + "\n").monitor.enabled)
  }
}
