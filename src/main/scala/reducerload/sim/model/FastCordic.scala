package reducerload.sim.model

import reducerload.cordic.CordicParams
import reducerload.fixedpoint.{FixedFormat, Rounding}

/**
 * [[reducerload.cordic.CordicModel.sinCosRaw]] in long arithmetic, for units whose formats all fit 62 bits:
 * same operations in the same order, every intermediate checked against the same format (tested equal to the
 * model, see FastFixedSpec). The BigInt model stays the reference.
 */
final class FastCordic(p: CordicParams) {
  private def fits(f: FixedFormat) = f.width <= 62
  private val zFormats = (p.firstIteration to p.iterations).map(p.zFormat)
  require(
    (zFormats ++ Seq(p.xyFormat, p.outputFormat) ++ (if (p.residual) Seq(p.zrFormat) else Nil)).forall(fits),
    s"FastCordic ${p.tag}: a format is wider than 62 bits"
  )

  private val lowBits = p.residualBits - p.tableBits
  require(lowBits >= 1, s"FastCordic ${p.tag}: no residual bits below the table index")
  private val segmentMask = (1L << p.tableBits) - 1
  private val lowMask = (1L << lowBits) - 1
  private val centre = 1L << (lowBits - 1)
  private val startX = p.startTable.map(_._1.toLong).toArray
  private val startY = p.startTable.map(_._2.toLong).toArray
  private val atan = p.atanTable.map(_.toLong).toArray
  private val zMin = zFormats.map(FastFixed.minOf).toArray // index i - firstIteration
  private val zMax = zFormats.map(FastFixed.maxOf).toArray
  private val (xyMin, xyMax) = (FastFixed.minOf(p.xyFormat), FastFixed.maxOf(p.xyFormat))
  private val (outMin, outMax) = (FastFixed.minOf(p.outputFormat), FastFixed.maxOf(p.outputFormat))
  private val (zrMin, zrMax) =
    if (p.residual) (FastFixed.minOf(p.zrFormat), FastFixed.maxOf(p.zrFormat)) else (0L, 0L)
  private val zrShift = p.zFracBits + p.twoPiFracBits - p.xyFormat.fracBits
  private val operandDrop = p.xyFormat.fracBits - p.residualOperandFracBits
  private val twoPi = p.twoPiRaw.toLong
  require(
    !p.residual || (zrShift >= 0 && operandDrop >= 0),
    s"FastCordic ${p.tag}: negative shift in the residual rotation"
  )

  /**
   * `v` if within [min, max]; the message names `what` (and the iteration, when not negative) only on
   * failure.
   */
  private def check(v: Long, min: Long, max: Long, what: String, iteration: Int = -1): Long = {
    if (v < min || v > max) {
      val where = if (iteration >= 0) s"$what after iteration $iteration" else what
      throw new IllegalArgumentException(s"CordicModel ${p.tag}: $where = $v outside [$min, $max]")
    }
    v
  }

  // The parameters as plain values, read into locals of the loop below (-Xcheckinit guards every field read).
  private val angleBits = p.angleBits
  private val residualBits = p.residualBits
  private val angleGuardBits = p.angleGuardBits
  private val firstIteration = p.firstIteration
  private val iterations = p.iterations
  private val residual = p.residual
  private val residualOperandFracBits = p.residualOperandFracBits
  private val guardBits = p.guardBits
  private val outputHalfUp = p.outputRounding == Rounding.HalfUp
  private val outputRounding = p.outputRounding

  /** Raw (cos, sin) of `angle` into `out(at)`, `out(at + 1)`. */
  def sinCosRaw(angle: Long, out: Array[Long], at: Int): Unit = {
    val firstIteration = this.firstIteration; val iterations = this.iterations
    val atan = this.atan; val zMin = this.zMin; val zMax = this.zMax; val xyMin = this.xyMin;
    val xyMax = this.xyMax
    require(
      angle >= 0 && angle < (1L << angleBits),
      s"CordicModel: angle code $angle is not a $angleBits-bit code"
    )
    val quadrant = (angle >> residualBits).toInt
    val segment = ((angle >> lowBits) & segmentMask).toInt
    var x = startX(segment)
    var y = startY(segment)
    var z =
      check(((angle & lowMask) - centre) << angleGuardBits, zMin(0), zMax(0), "z at the first iteration")
    var i = firstIteration
    while (i < iterations) {
      val dx = y >> i
      val dy = x >> i
      if (z >= 0) { x -= dx; y += dy; z -= atan(i) }
      else { x += dx; y -= dy; z += atan(i) }
      if (z < zMin(i + 1 - firstIteration) || z > zMax(i + 1 - firstIteration))
        check(z, zMin(i + 1 - firstIteration), zMax(i + 1 - firstIteration), "z", i)
      if (x < xyMin || x > xyMax) check(x, xyMin, xyMax, "x", i)
      if (y < xyMin || y > xyMax) check(y, xyMin, xyMax, "y", i)
      i += 1
    }
    if (residual) {
      val zr = check(Math.multiplyExact(z, twoPi) >> zrShift, zrMin, zrMax, "zr")
      val xt = x >> operandDrop
      val yt = y >> operandDrop
      val nx = x - (Math.multiplyExact(yt, zr) >> residualOperandFracBits)
      val ny = y + (Math.multiplyExact(xt, zr) >> residualOperandFracBits)
      x = check(nx, xyMin, xyMax, "x after the residual rotation")
      y = check(ny, xyMin, xyMax, "y after the residual rotation")
    }
    var c = x
    var s = y
    quadrant match {
      case 0 =>
      case 1 => c = -y; s = x
      case 2 => c = -x; s = -y
      case _ => c = y; s = -x
    }
    if (outputHalfUp && guardBits > 0) {
      c = Math.addExact(c, 1L << (guardBits - 1)) >> guardBits
      s = Math.addExact(s, 1L << (guardBits - 1)) >> guardBits
    } else {
      c = FastFixed.shiftRound(c, guardBits, outputRounding)
      s = FastFixed.shiftRound(s, guardBits, outputRounding)
    }
    out(at) = check(c, outMin, outMax, "output")
    out(at + 1) = check(s, outMin, outMax, "output")
  }
}
