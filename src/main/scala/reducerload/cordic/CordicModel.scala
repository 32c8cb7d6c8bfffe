package reducerload.cordic

import reducerload.fixedpoint.FixedFormat

/** One pipeline state: vector (x, y), residual angle z, and the quadrant riding beside them. */
final case class CordicState(x: BigInt, y: BigInt, z: BigInt, quadrant: Int)

/**
 * Bit-accurate integer model of [[CordicSinCos]]: same operations, same order, same widths. Every
 * intermediate is checked against the range the hardware format was derived from, so a wrong range proof
 * fails a test instead of wrapping silently.
 */
final class CordicModel(val p: CordicParams) {

  private def check(raw: BigInt, fmt: FixedFormat, what: String): BigInt = {
    require(fmt.contains(raw), s"CordicModel ${p.tag}: $what = $raw outside $fmt")
    raw
  }

  /**
   * Equation (10): split the binary angle into quadrant, table segment and z = the residual minus the
   * segment's centre; the start vector is the segment's table entry (45 degrees without a table).
   */
  def preprocess(angle: BigInt): CordicState = {
    require(
      angle >= 0 && angle.bitLength <= p.angleBits,
      s"CordicModel: angle code $angle is not a ${p.angleBits}-bit code"
    )
    val quadrant = (angle >> p.residualBits).toInt
    val lowBits = p.residualBits - p.tableBits
    val segment = ((angle >> lowBits) & ((BigInt(1) << p.tableBits) - 1)).toInt
    val low = angle & ((BigInt(1) << lowBits) - 1)
    val z = (low - (BigInt(1) << (lowBits - 1))) << p.angleGuardBits
    val (x, y) = p.startTable(segment)
    CordicState(x, y, check(z, p.zFormat(p.firstIteration), "z at the first iteration"), quadrant)
  }

  /** Equation (8): one micro-rotation by +-atan(2^-i), direction from the sign of z. */
  def rotate(s: CordicState, i: Int): CordicState = {
    val positive = s.z >= 0
    val dx = s.y >> i // arithmetic shift = floor, as the hardware wires it
    val dy = s.x >> i
    val x = if (positive) s.x - dx else s.x + dx
    val y = if (positive) s.y + dy else s.y - dy
    val z = if (positive) s.z - p.atanTable(i) else s.z + p.atanTable(i)
    val zNext = if (i + 1 <= p.iterations) check(z, p.zFormat(i + 1), s"z after iteration $i") else z
    CordicState(
      check(x, p.xyFormat, s"x after iteration $i"),
      check(y, p.xyFormat, s"y after iteration $i"),
      zNext,
      s.quadrant
    )
  }

  /** The multiply-based residual rotation (architecture = residual), as [[ResidualRotation]] computes it. */
  def residualRotate(s: CordicState): CordicState = {
    val zr =
      check((s.z * p.twoPiRaw) >> (p.zFracBits + p.twoPiFracBits - p.xyFormat.fracBits), p.zrFormat, "zr")
    val drop = p.xyFormat.fracBits - p.residualOperandFracBits
    val (xt, yt) = (s.x >> drop, s.y >> drop)
    val x = s.x - ((yt * zr) >> p.residualOperandFracBits)
    val y = s.y + ((xt * zr) >> p.residualOperandFracBits)
    CordicState(
      check(x, p.xyFormat, "x after the residual rotation"),
      check(y, p.xyFormat, "y after the residual rotation"),
      0,
      s.quadrant
    )
  }

  /** Equation (11) and output rounding: returns raw (cos, sin) in p.outputFormat. */
  def postprocess(s: CordicState): (BigInt, BigInt) = {
    val (c, sn) = s.quadrant match {
      case 0 => (s.x, s.y)
      case 1 => (-s.y, s.x)
      case 2 => (-s.x, -s.y)
      case _ => (s.y, -s.x)
    }
    def round(v: BigInt) =
      check(FixedFormat.shiftRound(v, p.guardBits, p.outputRounding), p.outputFormat, "output")
    (round(c), round(sn))
  }

  /** All states from z1 to the last iteration, for debugging and tests. */
  def trace(angle: BigInt): Seq[CordicState] =
    (p.firstIteration until p.iterations).scanLeft(preprocess(angle))(rotate)

  /** Raw (cos, sin) for an angle code. */
  def sinCosRaw(angle: BigInt): (BigInt, BigInt) = {
    val rotated = trace(angle).last
    postprocess(if (p.residual) residualRotate(rotated) else rotated)
  }

  /** (cos, sin) as doubles. */
  def sinCos(angle: BigInt): (Double, Double) = {
    val (c, s) = sinCosRaw(angle)
    (p.outputFormat.toDouble(c), p.outputFormat.toDouble(s))
  }

  /** The exact angle, in radians, that a code stands for. */
  def angleOf(code: BigInt): Double = 2 * math.Pi * code.toDouble / math.pow(2.0, p.angleBits)
}
