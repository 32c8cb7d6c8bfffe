package reducerload.regmap

import reducerload.compiler.Compiled
import reducerload.graph.{InertialParameter, Signal}
import reducerload.monitor.{JointField, RegisterKey}

/**
 * `<name>_layout.h`: the tables the C driver (driver/reducer_load.c) indexes by joint, from the same
 * [[CsrMap]].
 *
 * The register header names one macro per register, and a monitor figure's names depend on its width (`_w0`,
 * `_w1` only when it spans words) and its joint; widths differ between joints and designs, so no stride
 * reaches every joint. Here each joint's figures are one row of `{ byte offset of word 0, words, signed, SI
 * scale }` in [[JointField]] order, histogram bins last, so the driver loops over `RL_JOINTS` rows. The
 * run-time parameters are one row each `{ byte offset of word 0, words, fraction bits, width, lowest and
 * highest declared code }`: the declared range is not in the register map (the hardware clamps to it), and
 * the driver refuses a value beyond it rather than let it be clamped.
 */
object DriverLayout {

  /** A joint's figures in row order: the scalars, then the histogram bins. */
  def figures(bins: Int): Seq[JointField] = JointField.scalars ++ (0 until bins).map(JointField.HistogramBin)

  /** The C index macro of a figure of a joint's row. */
  def indexName(f: JointField): String = f match {
    case JointField.HistogramBin(b) => s"RL_FIG_HISTOGRAM_$b"
    case other                      => s"RL_FIG_${other.name.toUpperCase}"
  }

  /** One figure of one joint: where its least significant word is, how many words, signed, SI per code. */
  final case class Figure(byteOffset: Int, words: Int, signed: Boolean, scale: Option[Double])

  /** Each joint's figures, in [[figures]] order, from the monitor block of `m`. */
  def joints(m: CsrMap): IndexedSeq[IndexedSeq[Figure]] = {
    val firstWords = m.blocks.filter(_.block.name == "monitor").flatMap(_.registers).flatMap { r =>
      r.register.source match {
        case Source.Monitor(e, 0) =>
          e.key match {
            case RegisterKey.Joint(j, f) =>
              val scale = r.register.fields.flatMap(x => FieldFormat.scale(x.format)).headOption.map(_._1)
              Some((j, f, Figure(r.byteOffset, e.words, e.signed, scale)))
            case _ => None
          }
        case _ => None
      }
    }
    val joints = firstWords.map(_._1).distinct.sorted
    joints.map { j =>
      val row = firstWords.collect { case (`j`, f, figure) => f -> figure }.toMap
      val bins = row.keys.count(_.isInstanceOf[JointField.HistogramBin])
      require(
        row.keySet == figures(bins).toSet,
        s"register map ${m.name}: joint ${j + 1} lacks figures of ${figures(bins).map(_.name).mkString(", ")}"
      )
      figures(bins).map(row).toIndexedSeq
    }.toIndexedSeq
  }

  private def comment(s: String): String = s"/* $s */"

  /** A C99 double constant that reads back to `x` exactly. */
  private def double(x: Double): String = {
    val exponent = math.getExponent(x)
    if (x == math.pow(2.0, exponent)) s"0x1p$exponent" else java.lang.Double.toString(x)
  }

  /** The C index macro of a payload or gravity parameter, for the driver's SI payload. */
  def parameterIndexName(c: Compiled, s: Signal.Parameter): Option[String] = s match {
    case Signal.Inertial(j, par) if j == c.arm.chain.size - 1 =>
      Some("RL_PARAM_" + (par match {
        case InertialParameter.Mass          => "MASS"
        case InertialParameter.Com(a)        => "C" + "XYZ" (a)
        case InertialParameter.Inertia(r, k) => "I" + "XYZ" (r) + "XYZ" (k)
      }))
    case Signal.Gravity(axis) => Some("RL_PARAM_G" + "XYZ" (axis))
    case _                    => None
  }

  /** Every index macro the driver reads: -1 when the design has no such parameter. */
  private val allParameterNames: Seq[String] =
    Seq("MASS", "CX", "CY", "CZ", "IXX", "IXY", "IXZ", "IYY", "IYZ", "IZZ", "GX", "GY", "GZ").map(
      "RL_PARAM_" + _
    )

  def apply(c: Compiled, command: String): String = {
    val m = ReducerLoadRegisters(c)
    val n = c.arm.numerics
    val parameterRows = n.parameters.indices.map { k =>
      val words = m.registers.filter(_.register.source match {
        case Source.Parameter(`k`, _) => true
        case _                        => false
      })
      val (lo, hi) = n.parameterLimitRaw(n.parameters(k))
      val format = n.parameterPortFormat
      s"{ UINT32_C(${CsrEmitters.hex(words.head.byteOffset)}), ${words.size}, ${format.fracBits}, ${format.width}, " +
        s"INT64_C($lo), INT64_C($hi) }"
    }
    val indexOf = n.parameters.zipWithIndex.flatMap { case (s, k) =>
      parameterIndexName(c, s).map(_ -> k)
    }.toMap
    val rows = joints(m)
    val bins = rows.map(_.size - JointField.scalars.size)
    val maxBins = bins.maxOption.getOrElse(0)
    val guard = s"${m.name}_layout_h".toUpperCase
    val b = new StringBuilder
    def line(s: String = ""): Unit = b.append(s).append('\n')
    line("/*")
    (CsrEmitters.generatedBy(command) ++ Seq(
      "",
      s"Tables of ${m.meaning} for the C driver: each joint's monitor figures as one row of",
      "{ byte offset of the least significant word, words, signed, SI units per code (0: a count) },",
      "indexed by RL_FIG_*. The offsets are those of the register header."
    )).foreach(l => line(s" * $l".replaceAll("\\s+$", "")))
    line(" */")
    line(s"#ifndef $guard")
    line(s"#define $guard")
    line()
    line(s"#define RL_LAYOUT_HAS_MONITOR ${if (rows.isEmpty) 0 else 1}")
    val jointCount = m.register("id_shape").register.fields.find(_.name == "joints").map(_.reset)
    require(
      rows.isEmpty || jointCount.contains(BigInt(rows.size)),
      s"register map ${m.name}: ${rows.size} monitored joints"
    )
    line(s"#define RL_LAYOUT_JOINTS ${jointCount.getOrElse(BigInt(rows.size))}")
    line(s"#define RL_HISTOGRAM_BINS $maxBins ${comment("the most bins of any joint")}")
    line(s"#define RL_LAYOUT_JOINT_BINS { ${bins.mkString(", ")} } ${comment("each joint's bins")}")
    line(s"#define RL_FIGURES_PER_JOINT ${JointField.scalars.size + maxBins}")
    figures(maxBins).zipWithIndex.foreach { case (f, i) => line(s"#define ${indexName(f)} $i") }
    line()
    line(
      comment("one row per joint, one entry per figure; a joint with fewer bins has rows of 0 after its last")
    )
    line("#define RL_LAYOUT_MONITOR_FIGURES { \\")
    rows.zipWithIndex.foreach { case (row, j) =>
      val entries = row.map(f =>
        s"{ UINT32_C(${CsrEmitters.hex(f.byteOffset)}), ${f.words}u, ${if (f.signed) 1 else 0}u, ${f.scale.fold("0.0")(double)} }"
      ) ++ Seq.fill(maxBins + JointField.scalars.size - row.size)("{ UINT32_C(0x0), 0u, 0u, 0.0 }")
      val sep = if (j == rows.size - 1) "" else ","
      line(s"  { /* joint ${j + 1} */ \\")
      entries.zipWithIndex.foreach { case (e, i) =>
        line(s"    $e${if (i == entries.size - 1) "" else ","} \\")
      }
      line(s"  }$sep \\")
    }
    line("}")
    line()
    line(s"#define RL_LAYOUT_PARAMETERS ${parameterRows.size}")
    allParameterNames.foreach(p => line(s"#define $p ${indexOf.getOrElse(p, -1)}"))
    if (parameterRows.nonEmpty) {
      line(
        comment(
          "one row per run-time parameter: offset of word 0, words, fraction bits, width, declared codes"
        )
      )
      line("#define RL_LAYOUT_PARAMETER_TABLE { \\")
      parameterRows.zipWithIndex.foreach { case (r, i) =>
        line(s"  $r${if (i == parameterRows.size - 1) "" else ","} \\")
      }
      line("}")
    }
    line()
    line(s"#endif /* $guard */")
    b.toString
  }
}
