package reducerload.app

import com.typesafe.config.{ConfigRenderOptions, ConfigValueFactory}
import chisel3.Data
import reducerload.arm.{ArmIO, ArmParams}
import reducerload.compiler.{DeviceFit, Fitted, Resource}
import reducerload.monitor.MonitoredArmIO
import reducerload.fixedpoint.FixedFormat
import reducerload.graph.{InertialParameter, Signal}
import reducerload.monitor.{JointField, MonitorParams}
import reducerload.sim.rtl.ModulePorts

import scala.jdk.CollectionConverters._

/**
 * The report of an arm emission (every joint by RNEA), computed from the parameters that built the hardware;
 * with `monitor`, of the arm with its reducer monitor ([[reducerload.monitor.MonitoredArm]]): the host ports,
 * the monitor's derivation, 20-year proof and register map too.
 */
final case class ArmReport(
    p: ArmParams,
    moduleName: String,
    command: String,
    estimate: Option[Estimate] = None,
    monitor: Option[MonitorParams] = None,
    fit: Option[Fitted] = None
) extends EmissionReport {
  def latency: Int = p.latency
  private val n = p.numerics
  private val joints = p.chain.joints
  private val counts = p.graph.counts
  private val schedule = p.schedule
  private val ii = schedule.clocksPerSample
  val throughput: String = if (ii == 1) "one sample per clock" else s"one sample every $ii clocks"

  /** The torque the datapath computes for joint `i`, if any (a closed form computes one joint's). */
  private def outputOf(i: Int) =
    p.analysis.outputs.indices.find(k => p.analysis.outputs(k).name == joints(i).name)
  private def torqueCells(i: Int, fmt: (Double, Double) => String, none: String) =
    outputOf(i).fold(none)(k => fmt(p.analysis.outputs(k).range.maxAbs, p.errorBounds(k)))

  private val io: ArmIO = monitor.fold(new ArmIO(p))(m => new MonitoredArmIO(p, m))
  private val table = new PortTable(moduleName, ModulePorts(io))

  /** Every port of the module once, named from its IO Bundle, with its format and meaning. */
  val ports: Seq[PortRow] = {
    def at(leaf: Data, text: String) = table(leaf, text)
    val described = table.clockAndReset ++ Seq(
      at(io.in.valid, "1 bit: a sample this cycle"),
      at(
        io.in.ready,
        if (ii == 1) "1 bit: always high (one sample per clock)"
        else s"1 bit: high one clock in $ii (a sample is taken then; the units are busy with it in between)"
      )
    ) ++
      joints.indices.map(j =>
        at(
          io.in.bits.q(j),
          s"unsigned ${n.angleBits} bits, binary angle of ${joints(j).name}: rad = code * 2 pi / 2^${n.angleBits}"
        )
      ) ++
      joints.indices.map(j =>
        at(
          io.in.bits.qd(j),
          s"${n.velocityPortFormat.describe}, rad/s, declared |qd${j + 1}| <= ${n.velocityLimits(j)}"
        )
      ) ++
      joints.indices.map(j =>
        at(
          io.in.bits.qdd(j),
          s"${n.accelerationPortFormat.describe}, rad/s^2, declared |qdd${j + 1}| <= ${n.accelerationLimits(j)}"
        )
      ) ++
      io.in.bits.payload.toSeq.flatMap(_.zip(n.parameters).map { case (port, s) =>
        val what = s match {
          case Signal.Inertial(_, parameter) =>
            val unit = parameter match {
              case InertialParameter.Mass       => "kg"
              case InertialParameter.Com(_)     => "m"
              case _: InertialParameter.Inertia => "kg m^2"
            }
            s"$unit, payload $parameter in the frame of ${p.payload.fold("")(_.frame)}"
          case g: Signal.Gravity => s"m/s^2, gravity $g in base coordinates"
        }
        val r = n.parameterRanges(s)
        at(
          port,
          s"${n.parameterPortFormat.describe}, $what, declared in [${r.lo}, ${r.hi}] (beyond: clamped, every joint flagged)"
        )
      }) ++
      Seq(at(io.out.valid, s"1 bit: the torques of the sample given ${p.latency} cycles earlier")) ++
      p.analysis.outputs.indices.map(j =>
        at(
          io.out.bits.tau(j),
          s"${p.analysis.outputPortFormat.describe}, N·m, torque of ${p.analysis.outputs(j).name}"
        )
      ) ++
      joints.indices.map(j =>
        at(
          io.out.bits.outOfRange(j),
          s"1 bit: qd${j + 1} or qdd${j + 1}" + (if (p.payload.isDefined) " or a payload parameter" else "") +
            " of this sample was beyond its declared range (clamped)"
        )
      ) ++
      ((io, monitor) match {
        case (m: MonitoredArmIO, Some(mp)) =>
          Seq(
            at(
              m.host.snapshot,
              s"1 bit, pulse: copy every joint's live monitor state into the shadow bank (samples whose torques left io_out before this cycle)"
            ),
            at(
              m.host.clear,
              "1 bit, pulse: reset the live monitor state (the torques on io_out in this cycle are the first of the new period)"
            ),
            at(
              m.host.snapshotDone,
              s"1 bit: the shadow bank holds the snapshot (${mp.snapshotLatency} cycles after the pulse)"
            ),
            at(
              m.host.readAddress,
              s"unsigned ${mp.addressBits} bits: word address into the shadow bank (register map below)"
            ),
            at(
              m.host.readData,
              "32 bits: the word at the previous cycle's address (read latency 1, no side effects)"
            )
          )
        case _ => Nil
      })
    table.complete(described)
  }

  def portLines: Seq[String] = table.lines(ports, 26)

  private def jointLines: Seq[String] = joints.zipWithIndex.map { case (j, i) =>
    val a = j.axis
    f"  ${i + 1}%d ${j.name}%-24s ${j.kind}%-10s axis (${a.x}%.4f, ${a.y}%.4f, ${a.z}%.4f), body ${j.body.mass}%.4f kg; " +
      f"|qd| <= ${n.velocityLimits(i)} rad/s, |qdd| <= ${n.accelerationLimits(i)} rad/s^2" +
      torqueCells(
        i,
        (range, bound) => f"; torque range $range%.3f N·m, error bound $bound%.3e N·m",
        "; no torque computed"
      )
  }

  /**
   * The budget the interval's floor is computed for: the declared one, else the blocks this schedule uses.
   */
  private val limitBudget = schedule.request.maxMultipliers.getOrElse(schedule.multiplierBlocks)
  private val clocksFloor = schedule.clocksLowerBound(limitBudget)

  /** The latency the dependences allow with this design's operator latencies (unlimited units). */
  private val latencyFloor = p.banked.fold(schedule.dependenceBound)(_.dependenceBound)

  /**
   * With `schedule.scheduler = cp-sat`: how the solver's schedule stands against these units' optimum and the
   * list's.
   */
  private def solverBound: String = schedule.shorter.fold("") { s =>
    val stages = schedule.outputStages
    "; CP-SAT: " + (if (s.optimal) "the shortest" else s"at least ${s.provedBound + stages}") +
      s" with these units, the list schedule ${schedule.listLatency}"
  }
  private val adderUnits = p.banked.map(_.adderUnits)
  private def adderUtilization: Double =
    (counts.additions + counts.negations).toDouble / (adderUnits
      .getOrElse(counts.additions + counts.negations)
      .max(1)
      .toLong * ii)

  /**
   * How far the schedule is from what its operation counts allow (issue: print the distance, do not guess).
   */
  private def limitsLine: String =
    f"Limits: at least ${clocksFloor.fold("-")(_.toString)} clocks per sample for ${schedule.blockMultiplies} products on blocks " +
      f"and ${counts.sinCos} sin/cos pairs in $limitBudget blocks (achieved $ii); multiplier slots used ${schedule.multiplierUtilization * 100}%.1f%%, " +
      f"adder slots used ${adderUtilization * 100}%.1f%%" +
      s"; latency at least $latencyFloor cycles from the dependences (achieved ${p.latency}$solverBound)"

  /** Register bits holding values between cycles (at one clock per sample: the delay lines, as built). */
  private def heldBits: Long = if (schedule.dedicated) schedule.heldBits else p.heldRegisterBits

  /** Block-RAM delays of held values in a shared registers datapath. */
  private def heldDelays: Int = p.graph.ids.flatMap(p.heldTaps(_)).map(_.delayed.size).sum

  /** Products read off their unit's output past registered routes (`schedule.forward-slack`). */
  private def forwardedPastRoutes: Int = if (schedule.routed) p.graph.ids.count(schedule.forwarded) else 0

  /** The runs of parallel axes RNEA crosses in one rotation (`datapath.compose-parallel-axes`), if any. */
  private def composedRuns: String =
    if (p.composedRuns.isEmpty) ""
    else
      p.composedRuns
        .map(r => s"joints ${r.head + 1}-${r.last + 1}")
        .mkString("; parallel axes crossed in one rotation: ", ", ", "")

  def summaryLines: Seq[String] = estimate.toSeq.flatMap(_.lines) ++ Seq(
    s"Computes: ${p.dynamics.description}" + composedRuns,
    s"Robot: ${p.chain.name}, ${joints.size} moving joints (numbered from the base), gravity ${p.chain.gravity.toSeq.mkString("(", ", ", ")")} m/s^2" +
      p.gravity.fold("")(g => s" at reset; run-time gravity, each component within ±${g.maxMagnitude} m/s^2"),
    "Joints kept:"
  ) ++ jointLines ++ Seq(
    s"Operations after constant folding and sharing: ${counts.multiplications} multiplications (${counts.constantMultiplications} by a constant), " +
      s"${counts.additions} additions/subtractions, ${counts.negations} negations, ${counts.sinCos} sin/cos pairs (CORDIC units)",
    s"Schedule: $throughput, latency ${p.latency} cycles; multiplier units: ${schedule.unitSummary} (operand bits)" +
      s", ${schedule.multiplierBlocks} 18x18 blocks${schedule.request.maxMultipliers.fold("")(b => s" (budget $b)")}; " +
      s"${schedule.cordicUnits} CORDIC units for ${counts.sinCos} angles; " + p.banked.fold(
        s"${counts.additions + counts.negations - schedule.accumulations.map(_.inner.size).sum} adders; " +
          s"$heldBits register bits hold values between cycles" +
          (if (schedule.sharedRegisters.isEmpty) ""
           else
             s" (${schedule.sharedRegisters.map(_.members.size).sum} products take turns in " +
               s"${schedule.sharedRegisters.size} shared registers)") +
          (if (schedule.readerCopies.isEmpty) ""
           else
             s" (${schedule.readerCopyCount} readers' copies of ${schedule.readerCopies.size} " +
               "values)") +
          (if (heldDelays == 0) "" else s", $heldDelays block-RAM delays the longer stretches") +
          (if (schedule.productMemories.isEmpty) ""
           else
             s"; ${schedule.productMemoryOf.size} products read from ${schedule.productMemories.size} block RAMs " +
               "their units write (schedule.product-memories)") +
          (if (schedule.sinCosMemories.isEmpty) ""
           else
             s"; ${schedule.sinCosMemoryOf.size} sin/cos reads from ${schedule.sinCosMemories.size} block RAMs " +
               "the CORDIC units write (schedule.sin-cos-memories)") +
          (if (forwardedPastRoutes == 0) ""
           else
             s"; $forwardedPastRoutes products taken off their units by their one adder " +
               s"(schedule.forward-slack ${schedule.request.forwardSlack.get})") +
          (if (schedule.accumulations.isEmpty) ""
           else
             s"; ${schedule.accumulations.map(_.terms.size).sum} products summed by ${schedule.accumulations.size} " +
               s"accumulators (schedule.accumulate-slack ${schedule.request.accumulateSlack.get})")
      )(b =>
        s"storage memory: ${b.adderUnits} adder units for ${counts.additions + counts.negations} additions, ${b.banks.size} banks of block RAM " +
          s"(two read ports each, ${b.memoryBits} bits), latency bound from dependences ${b.dependenceBound} cycles; list order ${b.listOrder} (" +
          b.latencyByOrder
            .map { case (order, latency) => s"$order: ${latency.fold("no schedule")(l => s"$l cycles")}" }
            .mkString(", ") +
          s"; by-height the best of ${schedule.request.listTries} tries)"
      ),
    limitsLine,
    f"Derived worst-case error bound: ${p.errorBound}%.3e N·m (largest over the torques; vs the double-precision dynamics at the unquantized inputs)",
    s"Fraction bits: velocity ${p.velocityFracBits}, acceleration ${p.accelerationFracBits}, constants ${p.constantFracBits}, " +
      s"products and sums ${p.internalFracBits}, output ${p.outputFracBits} (numeric.target-error, when set, chose them" +
      (if (p.fracBitLimits.isEmpty) ")"
       else s"; ${p.fracBitLimits.byNode.size} constants and products have fewer, see every node's format)"),
    s"Output format: ${p.analysis.outputPortFormat}; widest internal node: ${p.analysis.widest._2.format}"
  ) ++ schedule.cordic.report.linesIterator.toSeq ++ monitorLines

  /** The monitor's derivation, 20-year proof and register map (plain text, for the emitted header). */
  private def monitorLines: Seq[String] = monitor.toSeq.flatMap { m =>
    Seq("", "Reducer life and limit monitor (docs/monitor.md):") ++ m.summaryLines.map("  " + _) ++
      Seq(
        s"Register map (word address; byte address = 4 x word; multi-word values least significant word first):"
      ) ++
      m.registerMap.entries.map(e =>
        f"  ${e.address}%4d  ${e.name}%-40s ${e.width}%3d bits${if (e.signed) " signed" else ""}%-7s ${e.meaning}"
      )
  }

  /** Each resource against the device: name, used, capacity, percent. */
  private def deviceRows(f: Fitted): Seq[(String, Int, Int, Double)] = Resource.all.map { r =>
    val cap = r.capacity(f.target.part)
    val used = r.used(f.design.resources)
    (
      r.unit(f.target.part) + (if (r == Resource.LogicElements) " (predicted)" else ""),
      used,
      cap,
      100.0 * used / cap
    )
  }

  /** The report's device section: use against the device and the design's warnings. */
  private def deviceMarkdown: Seq[String] = fit.toSeq.flatMap { f =>
    val d = f.target.part
    Seq(
      "",
      "## Device",
      "",
      s"${f.line}.",
      "",
      s"Target ${d.name} (${d.family}); logic headroom ${math.round(f.target.maxLogicFraction * 100)}% " +
        "(device.max-logic-fraction). Memory blocks counted from the memories the generator builds, logic " +
        s"predicted within about ${math.round(reducerload.compiler.ResourceModel.logicTolerance * 100)}% " +
        "of the open-tool estimate (docs/device.md).",
      "",
      "| resource | used | device | use |",
      "| --- | --- | --- | --- |"
    ) ++ deviceRows(f).map { case (name, used, cap, pct) =>
      f"| $name | ${DeviceFit.grouped(used)} | ${DeviceFit.grouped(cap)} | $pct%.1f%% |"
    } ++ {
      val all = p.chain.warnings ++ f.warnings
      if (all.isEmpty) Nil else "" +: "Warnings:" +: "" +: all.map(w => s"- $w")
    }
  }

  def markdown: String = (Seq(
    s"# $moduleName",
    "",
    s"- latency: ${p.latency} cycles; throughput: $throughput; ${schedule.multiplierBlocks} 18x18 multiplier blocks (${schedule.multiplierUnits} multiplier units, ${schedule.cordicUnits} CORDIC units)",
    f"- derived error bound: ${p.errorBound}%.3e N·m (largest over the torques)",
    s"- regenerate: `$command`",
    "",
    "## Ports",
    "",
    "| port | dir | format |",
    "| --- | --- | --- |"
  ) ++ table.markdown(ports) ++ deviceMarkdown ++ Seq(
    "",
    "## Joints",
    "",
    "| # | joint | type | axis | max velocity (rad/s) | max acceleration (rad/s^2) | torque range (N·m) | error bound (N·m) |",
    "| --- | --- | --- | --- | --- | --- | --- | --- |"
  ) ++ joints.indices.map { i =>
    val j = joints(i)
    f"| ${i + 1} | ${j.name} | ${j.kind} | (${j.axis.x}%.4f, ${j.axis.y}%.4f, ${j.axis.z}%.4f) | ${n.velocityLimits(i)} | ${n.accelerationLimits(i)} | " +
      torqueCells(i, (range, bound) => f"$range%.3f | $bound%.3e |", "- | - |")
  } ++ monitor.toSeq.flatMap(m =>
    Seq(
      "",
      "## Reducer monitor register map",
      "",
      s"${m.registerMap.words} words of 32 bits, read on io_host_readAddress / io_host_readData (docs/monitor.md, \"Host interface\").",
      ""
    ) ++
      m.registerMap.markdown
  ) ++ Seq("", "## Details", "", "```") ++ summaryLines ++ Seq("```") ++ Seq(
    "",
    "## Every node (derived from the declared ranges)",
    "",
    "Range: the exact value's interval over the declared inputs; error: the derived worst case of the datapath's value; format: Q(integer.fraction) bits, sign included.",
    "",
    "| node | range | error | format | width |",
    "| --- | --- | --- | --- | --- |"
  ) ++ p.graph.ids.map { id =>
    val a = p.analysis(id)
    f"| `${p.graph.describe(id)}` | [${a.range.lo}%.4g, ${a.range.hi}%.4g] | ${a.error}%.3e | ${a.format} | ${a.format.width} |"
  }).mkString("", "\n", "\n")

  def json: String = {
    def fmt(f: FixedFormat) =
      Map("int_bits" -> f.intBits, "frac_bits" -> f.fracBits, "width" -> f.width).asJava
    val m = Map[String, Any](
      "top" -> moduleName,
      "latency_cycles" -> p.latency,
      "clocks_per_sample" -> ii,
      "schedule" -> Map[String, Any](
        "clocks_per_sample" -> ii,
        "multiplier_units" -> schedule.multiplierUnits,
        "multiplier_unit_shapes" -> schedule.unitSummary,
        "multiplier_blocks" -> schedule.multiplierBlocks,
        "max_multipliers" -> schedule.request.maxMultipliers.map(Int.box).orNull,
        "cordic_units" -> schedule.cordicUnits,
        "storage" -> schedule.request.stored.name,
        "held_register_bits" -> p.banked.fold(heldBits)(_ => 0L),
        "adder_units" -> p.banked.fold(counts.additions + counts.negations)(_.adderUnits),
        "bank_memory_bits" -> p.banked.fold(0L)(_.memoryBits),
        "clocks_per_sample_lower_bound" -> clocksFloor.map(Int.box).orNull,
        "lower_bound_budget_blocks" -> limitBudget,
        "multiplier_utilization" -> schedule.multiplierUtilization,
        "adder_utilization" -> adderUtilization,
        "latency_lower_bound_cycles" -> latencyFloor
      ).asJava,
      "command" -> command,
      "model" -> p.dynamics.name,
      "robot" -> p.chain.name,
      "joints" -> joints.indices
        .map { i =>
          val j = joints(i)
          Map[String, Any](
            "name" -> j.name,
            "type" -> j.kind.name,
            "axis" -> j.axis.toSeq.map(Double.box).asJava,
            "max_velocity" -> n.velocityLimits(i),
            "max_acceleration" -> n.accelerationLimits(i)
          ) ++
            outputOf(i)
              .map(k =>
                Map(
                  "torque_range_nm" -> p.analysis.outputs(k).range.maxAbs,
                  "error_bound_nm" -> p.errorBounds(k)
                )
              )
              .getOrElse(Map.empty)
        }
        .map(_.asJava)
        .asJava,
      "outputs" -> p.analysis.outputs
        .map(o =>
          Map[String, Any](
            "name" -> o.name,
            "range_nm" -> o.range.maxAbs,
            "error_bound_nm" -> o.errorBound,
            "format" -> fmt(o.format)
          ).asJava
        )
        .asJava,
      "operations" -> Map(
        "multiplications" -> counts.multiplications,
        "constant_multiplications" -> counts.constantMultiplications,
        "additions" -> counts.additions,
        "negations" -> counts.negations,
        "sin_cos" -> counts.sinCos
      ).asJava,
      "multiplier_blocks" -> schedule.multiplierBlocks,
      "error_bound_nm" -> p.errorBound,
      "frac_bits" -> Map(
        "velocity" -> p.velocityFracBits,
        "acceleration" -> p.accelerationFracBits,
        "constant" -> p.constantFracBits,
        "internal" -> p.internalFracBits,
        "output" -> p.outputFracBits
      ).asJava,
      "frac_bit_capped_nodes" -> p.fracBitLimits.byNode.size,
      "angle_bits" -> n.angleBits,
      "velocity_format" -> fmt(n.velocityPortFormat),
      "acceleration_format" -> fmt(n.accelerationPortFormat),
      "output_format" -> fmt(p.analysis.outputPortFormat),
      "cordic" -> Map(
        "tag" -> schedule.cordic.tag,
        "latency_cycles" -> schedule.cordic.latency,
        "error_bound" -> schedule.cordic.errorBound
      ).asJava,
      "estimate" -> estimate.map(_.toMap.asJava).orNull
    ) ++ monitor.map(m => "monitor" -> ArmReport.monitorJson(m).asJava) ++ fit.map { f =>
      "device" -> Map[String, Any](
        "name" -> f.target.part.name,
        "family" -> f.target.part.family.name,
        "max_logic_fraction" -> f.target.maxLogicFraction,
        "chosen_by_fit" -> f.chosen,
        "summary" -> f.line,
        "resources" -> deviceRows(f).map { case (name, used, cap, pct) =>
          Map[String, Any]("resource" -> name, "used" -> used, "capacity" -> cap, "percent" -> pct).asJava
        }.asJava,
        "warnings" -> (p.chain.warnings ++ f.warnings).map(_.toString).asJava
      ).asJava
    }
    ConfigValueFactory
      .fromMap(m.asJava)
      .render(ConfigRenderOptions.concise().setJson(true).setFormatted(true)) + "\n"
  }
}

object ArmReport {

  /**
   * The monitor's parameters, accumulator widths with their 20-year proof, and register map, for report.json.
   */
  def monitorJson(m: MonitorParams): Map[String, Any] = {
    def fmt(f: FixedFormat) =
      Map("int_bits" -> f.intBits, "frac_bits" -> f.fracBits, "width" -> f.width).asJava
    Map[String, Any](
      "sample_period_s" -> m.samplePeriodS,
      "target_years" -> m.targetYears,
      "sample_budget" -> m.sampleBudget.toString,
      "update_stage_cycles" -> m.updateStage,
      "snapshot_latency_cycles" -> m.snapshotLatency,
      "address_bits" -> m.addressBits,
      "register_words" -> m.registerMap.words,
      "joints" -> (0 until m.joints).map { j =>
        Map[String, Any](
          "name" -> m.jointNames(j),
          "torque_format" -> fmt(m.torqueFormats(j)),
          "velocity_format" -> fmt(m.velocityFormats(j)),
          "repeated_peak_nm" -> m.repeatedPeakNm(j),
          "repeated_peak_code" -> m.repeatedPeakCode(j).toString,
          "momentary_peak_nm" -> m.momentaryPeakNm(j),
          "momentary_peak_code" -> m.momentaryPeakCode(j).toString,
          "life_exponent" -> m.lifeExponents(j),
          "gear_ratio" -> m.gearRatios(j),
          "histogram_bins" -> m.histogramBins(j),
          "histogram_bin_width_nm" -> m.histogramBinWidthNm(j),
          "power_error_relative" -> m.powerRelativeBound(j),
          "power_error_absolute" -> m.powerAbsoluteBound(j),
          "power_relative_from_u" -> math.pow(2.0, -m.powerTables(j).octaves),
          "power_value_frac_bits" -> m.powerTables(j).valueFracBits,
          "multiplier_blocks" -> m.multiplierBlocks(j),
          "accumulators" -> m.provenAccumulators.map { f =>
            Map[String, Any](
              "name" -> f.name,
              "bits" -> m.accumulatorBits(j, f),
              "max_increment" -> m.maxIncrement(j, f).toString,
              "worst_case" -> (m.maxIncrement(j, f) * m.sampleBudget).toString
            ).asJava
          }.asJava,
          "histogram_counter_bits" -> m.fieldWidth(j, JointField.HistogramBin(0))
        ).asJava
      }.asJava,
      "registers" -> m.registerMap.entries.map { e =>
        Map[String, Any](
          "word" -> e.address,
          "byte" -> 4 * e.address,
          "name" -> e.name,
          "bits" -> e.width,
          "words" -> e.words,
          "signed" -> e.signed,
          "meaning" -> e.meaning
        ).asJava
      }.asJava
    )
  }
}
