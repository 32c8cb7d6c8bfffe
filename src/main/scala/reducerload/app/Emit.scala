package reducerload.app

import chisel3.RawModule
import circt.stage.ChiselStage
import reducerload.arm.ArmDatapath
import reducerload.config.Settings
import reducerload.cordic.CordicSinCos
import reducerload.compiler.Compiled
import reducerload.monitor.MonitoredArm
import reducerload.config.BusKind
import reducerload.packaging.Packaging
import reducerload.pipeline.MultiplierImpl
import reducerload.regmap.{
  CsrEmitters,
  CsrFile,
  DriverLayout,
  ReducerLoadAvalon,
  ReducerLoadAxi,
  ReducerLoadRegisters
}
import reducerload.util.{InputError, OutputFile}

import java.nio.file.Path

/** Which module to emit. */
sealed abstract class Top(val name: String)
object Top {
  case object Load extends Top("load")
  case object SinCos extends Top("sincos")
  val all: Seq[Top] = Seq(Load, SinCos)
}

/**
 * What an emission produced, in memory until written; `registerFiles`: the register map's C header, reference
 * and SystemRDL (a design with the monitor).
 */
final case class Emission(
    topModule: String,
    verilog: String,
    reportMd: String,
    reportJson: String,
    config: String,
    registerFiles: Seq[CsrFile] = Nil
)

/**
 * The module that is the top of a design: its name and a generator of fresh instances (call it inside
 * `ChiselStage` or a parent's `Module(...)`).
 */
final case class TopModule(name: String, generator: () => RawModule)

object Emit {

  /**
   * Which module is the top of `c`'s design (`--top load`), the one place that chooses it (emission and the
   * library API, [[reducerload.api.ReducerLoad]]): the `bus.interface` wrapper named `bus.top-name`, or
   * without a bus the monitored arm or the bare datapath.
   */
  def topModule(c: Compiled)(implicit multiplierImpl: MultiplierImpl): TopModule = {
    val arm = c.arm
    val bus = c.config.bus
    bus.kind match {
      case BusKind.Avalon =>
        TopModule(
          bus.topName,
          () => new ReducerLoadAvalon(arm, c.monitor, ReducerLoadRegisters(c), bus.topName)
        )
      case BusKind.Axi =>
        TopModule(bus.topName, () => new ReducerLoadAxi(arm, c.monitor, ReducerLoadRegisters(c), bus.topName))
      case BusKind.Bare =>
        c.monitor match {
          case Some(monitor) => TopModule(s"MonitoredArm_${arm.tag}", () => new MonitoredArm(arm, monitor))
          case None          => TopModule(arm.moduleName, () => new ArmDatapath(arm))
        }
    }
  }

  /** `c` without the bus wrapper: the design the simulators' harnesses drive (ports as [[ArmDatapath]]'s). */
  def bare(c: Compiled): Compiled =
    c.copy(config = c.config.copy(bus = c.config.bus.copy(kind = BusKind.Bare)))

  /**
   * The report of `c`'s top (`--top load`) without elaborating it; `estimate(module)`: the resource estimate
   * of a module of the emitted body. A wrapper's report gives its own resources beside the datapath's.
   */
  def loadReport(
      c: Compiled,
      command: String,
      estimate: String => Option[Estimate] = _ => None
  ): EmissionReport = {
    val arm = c.arm
    val name = topModule(c).name
    val bare = c.config.bus.kind == BusKind.Bare
    val inner = if (bare) name else c.monitor.fold(arm.moduleName)(_ => s"MonitoredArm_${arm.tag}")
    val datapath = ArmReport(arm, inner, command, estimate(inner), c.monitor, Some(c.fit))
    if (bare) datapath else WrapperReport(c, name, datapath, estimate(name))
  }

  /**
   * firtool options for Quartus on Cyclone IV: no randomization or `ifdef` initial blocks, no SystemVerilog
   * local variables in always blocks, no packed arrays, no source locator comments (byte-identical output
   * from any checkout path).
   */
  val firtoolOpts: Array[String] = Array(
    "-disable-all-randomization",
    "-strip-debug-info",
    "--lowering-options=disallowLocalVariables,disallowPackedArrays,locationInfoStyle=none,omitVersionComment"
  )

  val options: Seq[Opt] = Seq(
    Opt("target-dir", "DIR", "where the Verilog and reports go", "generated"),
    Opt(
      "top",
      "load|sincos",
      "emit the datapath (every torque the model computes) or one CORDIC sin/cos unit",
      "load"
    )
  )
  val flags: Seq[String] = Seq("estimate", "fmax")
  val flagHelp: Map[String, String] = Map(
    "estimate" -> "add the open-tool Cyclone IV resource estimate to the reports (needs python3 and yosys)",
    "fmax" -> "also place and route on ECP5 for the Fmax proxy (about 2 minutes for the default; implies --estimate)"
  )

  def top(cli: Cli): Top = {
    val name = cli.get("top").getOrElse("load")
    Top.all
      .find(_.name == name)
      .getOrElse(throw new InputError(s"command line: --top must be load or sincos, got '$name'"))
  }

  private val fileMarker = """(?m)^// ----- 8< ----- FILE "([^"]*)" ----- 8< -----$""".r

  /**
   * `emitSystemVerilog` returns the design followed by the inline black boxes' Verilog, each after a `//
   * ----- 8< ----- FILE "name"` marker, and a file list (`.f`) for file-based flows. Drop the file list so
   * the one .sv file is the whole design and nothing else.
   */
  def withBlackBoxes(emitted: String): String = {
    val starts = fileMarker.findAllMatchIn(emitted).toSeq
    val ends = starts.drop(1).map(_.start) :+ emitted.length
    val fileLists = starts.zip(ends).filter { case (m, _) => m.group(1).endsWith(".f") }
    fileLists.reverse.foldLeft(emitted) { case (text, (m, end)) =>
      text.substring(0, m.start) + text.substring(end)
    }
  }

  /** What the integration tool shows for the component: the robot, its joints and the top's rate. */
  private def componentDescription(c: Compiled): String =
    s"reducer loads of ${c.arm.chain.name} (${c.arm.chain.size} joints), one sample every " +
      s"${c.arm.schedule.clocksPerSample} clocks, latency ${c.arm.latency} cycles"

  /** Elaborate and emit in memory; nothing touches the disk. */
  def emit(
      c: Compiled,
      top: Top,
      command: String,
      estimate: Boolean = false,
      fmax: Boolean = false
  ): Emission = {
    def verilog(gen: => RawModule) = withBlackBoxes(
      ChiselStage.emitSystemVerilog(gen, Array.empty[String], firtoolOpts)
    )
    def est(body: String, module: String) =
      if (estimate || fmax) Some(Estimate.run(body, module, fmax)) else None
    // The wrapper's integration component (Platform Designer, IP-XACT) is read from the module as elaborated.
    val (body, r: EmissionReport, component: Seq[CsrFile]) = top match {
      case Top.Load =>
        val t = topModule(c)
        val (module, body) = Packaging.elaborate(g => verilog(g))(t.generator())
        val r = loadReport(c, command, module => est(body, module))
        (body, r, Packaging.files(module, c.config.bus.kind, componentDescription(c), command))
      case Top.SinCos =>
        val name = s"CordicSinCos_${c.config.cordic.tag}"
        val body = verilog(new CordicSinCos(c.config.cordic))
        (body, SinCosReport(c.config.cordic, name, command, est(body, name)), Nil)
    }
    val header = (Seq(
      s"Generated by the reducer-load generator. Do not edit: regenerate with",
      s"  $command",
      s"Top module: ${r.moduleName}, latency ${r.latency} cycles, ${r.throughput}.",
      ""
    ) ++ r.portLines ++ Seq("") ++ r.summaryLines)
      .map(l => if (l.isEmpty) "//" else s"// $l")
      .mkString("", "\n", "\n\n")
    val config =
      Settings.render(
        c.config,
        Seq("Effective configuration of this emission; regenerate with:", s"  $command")
      )
    // The register map's files and the C driver's layout tables, for a design with registers.
    def withRegisters = {
      val map = ReducerLoadRegisters(c)
      CsrEmitters.all(map, command) :+ CsrFile(s"${map.name}_layout.h", DriverLayout(c, command))
    }
    val registerFiles = (top, c.monitor) match {
      case (Top.Load, Some(_))                                   => withRegisters
      case (Top.Load, None) if c.config.bus.kind != BusKind.Bare => withRegisters
      case _                                                     => Nil
    }
    Emission(r.moduleName, header + body, r.markdown, r.json, config, registerFiles ++ component)
  }

  /** Write all files or none ([[OutputFile.writeAll]]). */
  def write(e: Emission, dir: Path): Seq[Path] =
    OutputFile.writeAll(
      dir,
      Seq(
        s"${e.topModule}.sv" -> e.verilog,
        "report.md" -> e.reportMd,
        "report.json" -> e.reportJson,
        "config.conf" -> e.config
      ) ++ e.registerFiles.map(f => f.name -> f.text)
    )

  def run(cli: Cli, commandLine: String): Unit = {
    val c = cli.compiled
    val t = top(cli)
    val dir = cli.pathOr("target-dir", "generated")
    val e = emit(c, t, commandLine, cli.has("estimate"), cli.has("fmax"))
    val written = write(e, dir)
    written.foreach(f => println(s"wrote $f"))
    if (t == Top.Load) println(c.fit.line)
    // The report's summary: title, latency, throughput, bound, regeneration command.
    println(e.reportMd.linesIterator.takeWhile(!_.startsWith("## ")).filter(_.nonEmpty).mkString("\n"))
  }
}
