package reducerload.cordic

import reducerload.fixedpoint.{FixedFormat, Rounding}

/** How the rotation is finished. */
sealed abstract class CordicArchitecture(val name: String) {
  override def toString: String = name
}
object CordicArchitecture {

  /** The paper's scheme: every micro-rotation is a shift-add stage. */
  case object Classic extends CordicArchitecture("classic")

  /**
   * After the shift-add iterations the residual angle z is below atan(2^-(n-1)), so one multiply-based
   * rotation x' = x - y zr, y' = y + x zr (zr = 2 pi z in radians) finishes the job on 18x18 multipliers:
   * about half the stages for the same accuracy.
   */
  case object ResidualRotation extends CordicArchitecture("residual")

  val all: Seq[CordicArchitecture] = Seq(Classic, ResidualRotation)
  def parse(s: String): Option[CordicArchitecture] = all.find(_.name == s)
}

/**
 * Parameters of the pipelined circular-rotation CORDIC (docs/equations.md, "The CORDIC unit"; paper section
 * 1.2).
 *
 * The angle enters as a binary angle: an unsigned `angleBits`-bit code, one full turn = 2^angleBits, so the
 * quadrant is the top two bits and angle sums wrap for free. Outputs are cos and sin in `outputFormat` =
 * Q1.(outputBits-2).
 *
 * @param angleBits
 *   width of the binary-angle input
 * @param outputBits
 *   width of each output (sign + 1 integer bit + fraction)
 * @param iterations
 *   micro-rotations i = 0 .. iterations-1; i = 0 (45 degrees) is always positive after quadrant folding, so
 *   it is folded into the start vector
 * @param guardBits
 *   extra fraction bits in x and y beyond the output's
 * @param angleGuardBits
 *   extra fraction bits in the angle accumulator z beyond the input's
 * @param outputRounding
 *   how x and y lose their guard bits at the output
 * @param iterationsPerStage
 *   micro-rotations between pipeline registers (latency against Fmax)
 * @param architecture
 *   classic shift-add only, or shift-add followed by one multiply-based residual rotation
 * @param tableBits
 *   0: the 45-degree iteration 0 is folded into a constant start vector. T > 0: the top T bits of the folded
 *   angle index a 2^T-entry sin/cos table (block-RAM ROM) that replaces iterations 0..T; shift-add starts at
 *   iteration T+1
 * @param tableRouteRegister
 *   with a table: one more register, in logic, after the table's data register (the block RAM's output
 *   register), so that the route from the block RAM to the first rotation stage has a clock of its own. The
 *   arm datapath's schedule sets it wherever routes are registered (`Schedule.cordic`): on a full device that
 *   route limits the clock
 */
final case class CordicParams(
    angleBits: Int = 26,
    outputBits: Int = 26,
    iterations: Int = 26,
    guardBits: Int = 5,
    angleGuardBits: Int = 5,
    outputRounding: Rounding = Rounding.HalfUp,
    iterationsPerStage: Int = 1,
    architecture: CordicArchitecture = CordicArchitecture.Classic,
    tableBits: Int = 0,
    tableRouteRegister: Boolean = false
) {

  require(angleBits >= 6 && angleBits <= 48, s"CordicParams.angleBits must be in 6..48, got $angleBits")
  require(outputBits >= 6 && outputBits <= 48, s"CordicParams.outputBits must be in 6..48, got $outputBits")
  require(guardBits >= 0 && guardBits <= 16, s"CordicParams.guardBits must be in 0..16, got $guardBits")
  require(
    angleGuardBits >= 0 && angleGuardBits <= 16,
    s"CordicParams.angleGuardBits must be in 0..16, got $angleGuardBits"
  )
  require(
    iterations >= 2,
    s"CordicParams.iterations must be >= 2 (i = 0 is folded into the start vector), got $iterations"
  )
  require(iterationsPerStage >= 1, s"CordicParams.iterationsPerStage must be >= 1, got $iterationsPerStage")
  require(
    tableBits >= 0 && tableBits <= 12,
    s"CordicParams.tableBits must be in 0..12 (a 2^tableBits-entry ROM), got $tableBits"
  )
  // A table with the residual rotation may leave no shift-add stage at all; without the residual
  // rotation at least one shift-add stage must follow the table.
  private val minIterations = tableBits + (if (architecture == CordicArchitecture.ResidualRotation) 1 else 2)
  require(
    iterations >= minIterations,
    s"CordicParams.iterations ($iterations) must be >= $minIterations: the table " +
      s"replaces iterations 0..$tableBits" +
      (if (architecture == CordicArchitecture.ResidualRotation) ""
       else " and at least one shift-add stage follows")
  )
  require(
    angleBits - 2 - tableBits >= 2,
    s"CordicParams.tableBits ($tableBits) leaves fewer than 2 angle bits below the table index"
  )

  /** The first shift-add iteration: the table (or the folded 45-degree start) covers the ones before. */
  val firstIteration: Int = tableBits + 1

  /** Output format of cos and sin: values in [-1, 1] need one integer bit for +1.0. */
  val outputFormat: FixedFormat = FixedFormat(1, outputBits - 2)

  /** x and y inside the pipeline: |x|, |y| <= 1 plus rounding, so Q1 with guard bits. */
  val xyFormat: FixedFormat = FixedFormat(1, outputFormat.fracBits + guardBits)

  require(
    iterations - 1 <= xyFormat.fracBits,
    s"CordicParams.iterations ($iterations) is more than the bits can use: stage i " +
      s"shifts by i bits and x/y have ${xyFormat.fracBits} fraction bits (outputBits - 2 + guardBits), so " +
      s"iterations must be <= ${xyFormat.fracBits + 1}"
  )

  /** z counts turns with this many fraction bits: the input code plus guard bits. */
  val zFracBits: Int = angleBits + angleGuardBits

  /** atan(2^-i) in z units (turns * 2^zFracBits), rounded half up; index i = 0 .. iterations-1. */
  val atanTable: IndexedSeq[BigInt] = (0 until iterations).map { i =>
    FixedFormat(0, zFracBits).quantize(math.atan(math.pow(2.0, -i)) / (2 * math.Pi), Rounding.HalfUp)
  }

  require(
    atanTable(iterations - 1) >= 2,
    s"CordicParams.iterations ($iterations) is more than the angle bits can use: " +
      s"atan(2^-${iterations - 1}) rounds to ${atanTable(iterations - 1)} LSB of a $zFracBits-bit angle " +
      s"(angleBits + angleGuardBits); use fewer iterations or more angle bits"
  )

  /** Product of the shift-add gains: the start vector has length K, so the result has length 1. */
  val gainK: Double =
    (firstIteration until iterations).map(i => 1.0 / math.sqrt(1.0 + math.pow(2.0, -2.0 * i))).product

  /** Width of one table segment in z units: a quarter turn split in 2^tableBits. */
  private val segmentRaw: BigInt = BigInt(1) << (zFracBits - 2 - tableBits)

  /**
   * The start vectors: K (cos c, sin c) at the centre c of each segment, rounded half up. With tableBits = 0
   * the single entry is the 45-degree vector x1 = y1 = K cos 45 (iteration 0 folded).
   */
  val startTable: IndexedSeq[(BigInt, BigInt)] = (0 until (1 << tableBits)).map { k =>
    val centre = (k + 0.5) * (math.Pi / 2) / (1 << tableBits)
    (
      xyFormat.quantize(gainK * math.cos(centre), Rounding.HalfUp),
      xyFormat.quantize(gainK * math.sin(centre), Rounding.HalfUp)
    )
  }

  /**
   * Bit columns of the start table's word (x then y, `xyFormat.width` bits each, as QuadrantPreprocessor
   * stores it) that differ between entries: synthesis stores no other column (every vector lies in the first
   * quadrant, so the sign bits and the top bits of a large table never change).
   */
  lazy val startTableVaryingBits: Int = {
    val w = xyFormat.width
    val mask = (BigInt(1) << w) - 1
    val words = startTable.map { case (x, y) => ((x & mask) << w) | (y & mask) }
    (0 until 2 * w).count(b => words.exists(_.testBit(b)) && !words.forall(_.testBit(b)))
  }

  /**
   * Bound on |z| entering iteration i (raw units), for i = firstIteration .. iterations: half a segment at
   * the start (45 degrees without a table), then |z_{i+1}| <= atan(2^-i) + 2 LSB (table rounding can break
   * the exact halving by up to 1.5 LSB). Convergence: half a segment, (pi/4) 2^-T rad, is below 2
   * atan(2^-(T+1)) for every T.
   */
  def zBoundRaw(i: Int): BigInt = {
    require(
      i >= firstIteration && i <= iterations,
      s"zBoundRaw: iteration $i out of $firstIteration..$iterations"
    )
    if (i == firstIteration) segmentRaw / 2 else atanTable(i - 1) + 2
  }

  /** Narrowest z format entering iteration i: z shrinks as the rotation converges. */
  def zFormat(i: Int): FixedFormat = FixedFormat.forRawRange(zBoundRaw(i), zFracBits)

  /** Width of the folded quadrant residual: the angle code without its two quadrant bits. */
  val residualBits: Int = angleBits - 2

  /** Rotation iterations in hardware (firstIteration .. iterations-1), grouped per pipeline stage. */
  val stageIterations: Seq[Seq[Int]] =
    (firstIteration until iterations).grouped(iterationsPerStage).map(_.toSeq).toSeq

  /**
   * Registers in logic after the table's block RAM: the route register, with a table and
   * `tableRouteRegister`.
   */
  val tableRouteRegisters: Int = if (tableBits > 0 && tableRouteRegister) 1 else 0

  /**
   * The table lookup is a ROM read with registered address and registered data: two more stages, and the
   * route register a third.
   */
  val tableLatency: Int = (if (tableBits > 0) 2 else 0) + tableRouteRegisters

  val residual: Boolean = architecture == CordicArchitecture.ResidualRotation

  /**
   * 18x18 blocks of one unit: the residual rotation's three products (z to radians, x zr, y zr), none for
   * classic.
   */
  val multiplierBlocks: Int = if (residual) 3 else 0

  // ---- residual rotation (architecture = residual) ----

  /** 2 pi in 17 bits (Q3.13): z (turns) times it fits one 18x18 multiplier with room for its sign. */
  val twoPiFracBits: Int = 13
  val twoPiRaw: BigInt = FixedFormat(3, twoPiFracBits).quantize(2 * math.Pi, Rounding.HalfUp)

  /** zr in radians, on the x/y scale; its range follows from z's proven range after the last iteration. */
  private val zResidualMaxTurns: Double = zBoundRaw(iterations).toDouble * math.pow(2.0, -zFracBits)
  val zrMaxAbs: Double = 2 * math.Pi * zResidualMaxTurns * (1 + 1e-6) + xyFormat.lsb
  val zrFormat: FixedFormat =
    FixedFormat.forRawRange(
      BigDecimal(zrMaxAbs * math.pow(2.0, xyFormat.fracBits))
        .setScale(0, BigDecimal.RoundingMode.CEILING)
        .toBigInt,
      xyFormat.fracBits
    )

  /**
   * x and y keep only the fraction bits that matter against |zr| < 2^e before they multiply: the truncation
   * then costs at most 2^-(F-e) * |zr| <= about one LSB of the product.
   */
  val residualOperandFracBits: Int = math.max(1, xyFormat.fracBits + math.getExponent(zrMaxAbs))
  val residualOperandFormat: FixedFormat = FixedFormat(1, residualOperandFracBits)

  if (residual) {
    require(
      iterations >= 4,
      s"CordicParams.iterations must be >= 4 with the residual rotation, got $iterations"
    )
    require(
      zFormat(iterations).width <= 18,
      s"CordicParams.iterations ($iterations) is too few for the residual rotation: z needs " +
        s"${zFormat(iterations).width} bits after the last iteration and its multiply by 2 pi must fit 18 " +
        s"bits; use more iterations or fewer angle bits"
    )
    require(
      residualOperandFormat.width <= 18 && zrFormat.width <= 18,
      s"CordicParams.iterations ($iterations) is too few for outputBits $outputBits + " +
        s"guardBits $guardBits: the residual products are ${residualOperandFormat.width} x " +
        s"${zrFormat.width} bits, more than one 18x18 multiplier"
    )
  }

  /** Clocks of the residual rotation: the 2 pi multiply, the x zr and y zr multiplies, the final add. */
  val residualLatency: Int = if (residual) 2 * reducerload.pipeline.SignedMultiply.latency + 1 else 0

  /**
   * Input register + rotation stages (+ residual rotation) + output stage (rounding and quadrant mapping).
   */
  val latency: Int = 1 + tableLatency + stageIterations.size + residualLatency + 1

  // ---- Analytic error budget (checked against double precision by the exhaustive/dense sweep tests) ----

  private val turnsPerZLsb: Double = math.pow(2.0, -zFracBits)

  /**
   * Angle error in radians. Classic: the residual left in z plus table rounding. Residual rotation: table
   * rounding, the conversion of z to radians (constant rounding, truncation), and the first-order rotation's
   * angle error atan(zr) - zr <= zr^3 / 3.
   */
  val angleErrorBound: Double = {
    val table = 2 * math.Pi * turnsPerZLsb * 0.5 * (iterations - firstIteration)
    if (!residual) 2 * math.Pi * turnsPerZLsb * (atanTable(iterations - 1) + 2).toDouble + table
    else {
      val twoPiError = math.abs(2 * math.Pi - twoPiRaw.toDouble * math.pow(2.0, -twoPiFracBits))
      table + zResidualMaxTurns * twoPiError + xyFormat.lsb + math.pow(zrMaxAbs, 3) / 3
    }
  }

  /** Residual rotation: its gain sqrt(1 + zr^2) and the truncations of its operands and products. */
  val residualRoundingBound: Double =
    if (!residual) 0.0
    else math.pow(zrMaxAbs, 2) / 2 + math.sqrt(2.0) * (xyFormat.lsb + residualOperandFormat.lsb * zrMaxAbs)

  /** Largest gain the remaining micro-rotations apply to an error injected after iteration 1. */
  val remainingGain: Double =
    (firstIteration until iterations).map(i => math.sqrt(1.0 + math.pow(2.0, -2.0 * i))).product

  /** Rounding of the start vector and the floor of each shifted operand, as an error vector length. */
  val rotationRoundingBound: Double =
    remainingGain * math.sqrt(2.0) * xyFormat.lsb * (0.5 + (iterations - firstIteration) * Rounding
      .maxErrorLsb(Rounding.Truncate))

  val outputRoundingBound: Double = Rounding.maxErrorLsb(outputRounding) * outputFormat.lsb

  /** Worst-case |error| of cos or sin against the exact value at the input code's angle. */
  val errorBound: Double =
    angleErrorBound + rotationRoundingBound + residualRoundingBound + outputRoundingBound

  /** Parameter-bearing name for emitted modules. */
  def tag: String =
    s"a${angleBits}_o${outputBits}_n${iterations}_g$guardBits" + (if (iterationsPerStage > 1)
                                                                    s"_r$iterationsPerStage"
                                                                  else "") +
      (if (residual) "_res" else "") + (if (tableBits > 0) s"_t$tableBits" else "") +
      (if (tableRouteRegisters > 0) "_tr" else "")

  /** The arctan table with its meaning, for reports and the emitted header. */
  def atanTableLines: Seq[String] = atanTable.zipWithIndex.map { case (raw, i) =>
    val hexDigits = (zFracBits + 3) / 4
    val degrees = raw.toDouble * turnsPerZLsb * 360.0
    f"i=$i%2d  atan(2^-$i%-2d) = " +
      f"0x${raw.toString(16).reverse.padTo(hexDigits, '0').reverse} = $degrees%.9f deg" +
      (if (i == 0) "  (folded into the start vector)" else "")
  }

  def report: String = {
    val lines = Seq(
      s"CORDIC sin/cos $tag",
      s"  angle input        : unsigned $angleBits-bit binary angle (full turn = " +
        s"2^$angleBits), quadrant = top 2 bits",
      s"  output cos, sin    : ${outputFormat.describe}, rounding $outputRounding",
      s"  x, y datapath      : ${xyFormat.describe}",
      s"  z accumulator      : turns * 2^$zFracBits, ${zFormat(firstIteration).width} bits at iteration " +
        s"$firstIteration down to ${zFormat(iterations).width} at the end",
      (if (tableBits == 0)
         f"  gain K             : $gainK%.15f (start vector x1 = y1 = " +
           f"0x${startTable.head._1.toString(16)}, iteration 0 folded)"
       else
         f"  gain K             : $gainK%.15f; start table: ${1 << tableBits} entries x " +
           f"${2 * xyFormat.width} bits = ${(1 << tableBits) * 2 * xyFormat.width} ROM bits, " +
           f"replacing iterations 0..$tableBits"),
      s"  iterations         : $firstIteration..${iterations - 1} shift-add ($iterationsPerStage per " +
        s"stage), latency $latency cycles, one angle per clock",
      f"  error bound        : $errorBound%.3e (2^${math.log(errorBound) / math.log(2)}%.1f) (angle " +
        f"$angleErrorBound%.3e, rotation rounding $rotationRoundingBound%.3e, output " +
        f"rounding $outputRoundingBound%.3e)"
    ) ++ (if (residual)
            Seq(
              s"  residual rotation  : zr = z * 0x${twoPiRaw.toString(16)} * 2^-$twoPiFracBits (2 " +
                s"pi), zr ${zrFormat.describe}; x, y truncated to $residualOperandFormat for x*zr, " +
                s"y*zr (one 18x18 multiplier each)",
              f"                       |zr| <= $zrMaxAbs%.3e rad, rounding bound $residualRoundingBound%.3e"
            )
          else Nil) ++ Seq(
      "  arctan table (turns * 2^" + zFracBits + "):"
    )
    (lines ++ atanTableLines.map("    " + _)).mkString("\n")
  }
}

object CordicParams {

  /** The paper's unit: 10 iterations, 16-bit angle and outputs. */
  val paper: CordicParams =
    CordicParams(angleBits = 16, outputBits = 16, iterations = 10, guardBits = 2, angleGuardBits = 2)

  /** Precise default: sin/cos error near 2^-23, what the load targets of the presets need. */
  val precise: CordicParams = CordicParams()

  /** A small unit whose every angle code can be simulated. */
  val small: CordicParams =
    CordicParams(angleBits = 10, outputBits = 12, iterations = 10, guardBits = 2, angleGuardBits = 4)

  /** About the precise preset's accuracy with half its shift-add stages and three 18x18 multipliers. */
  val residual: CordicParams =
    CordicParams(iterations = 14, architecture = CordicArchitecture.ResidualRotation)

  /** A small residual unit whose every angle code can be simulated. */
  val smallResidual: CordicParams =
    CordicParams(
      angleBits = 12,
      outputBits = 12,
      iterations = 6,
      guardBits = 2,
      angleGuardBits = 4,
      architecture = CordicArchitecture.ResidualRotation
    )

  /**
   * The residual unit with a 512-entry start table (block-RAM ROM, 512 x 62 bits) in place of iterations
   * 0..9: four shift-add stages remain before the residual rotation.
   */
  val tableResidual: CordicParams = residual.copy(tableBits = 9)

  /** A small table unit whose every angle code can be simulated. */
  val smallTable: CordicParams = small.copy(tableBits = 3)

  val presets: Map[String, CordicParams] =
    Map(
      "paper" -> paper,
      "precise" -> precise,
      "small" -> small,
      "residual" -> residual,
      "small-residual" -> smallResidual,
      "table-residual" -> tableResidual,
      "small-table" -> smallTable
    )
}
