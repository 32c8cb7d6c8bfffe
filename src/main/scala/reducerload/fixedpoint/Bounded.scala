package reducerload.fixedpoint

/**
 * Range and error of one signal: the exact value satisfies |v| <= maxAbs, and the datapath's value
 * differs from it by at most `error`. Formats come from `maxAbs + error`; the output error bound
 * is the `error` that propagates to the end. Used at elaboration only.
 */
final case class Bounded(maxAbs: Double, error: Double) {
  require(maxAbs >= 0 && error >= 0 && !maxAbs.isInfinite && !error.isInfinite && !maxAbs.isNaN && !error.isNaN,
    s"Bounded: range $maxAbs and error $error must be finite and non-negative")

  /** Largest magnitude the hardware can see. */
  def computedMaxAbs: Double = maxAbs + error

  def +(o: Bounded): Bounded = Bounded(maxAbs + o.maxAbs, error + o.error)

  /** |ab - a'b'| <= |a| e_b + e_a |b| + e_a e_b. */
  def *(o: Bounded): Bounded =
    Bounded(maxAbs * o.maxAbs, maxAbs * o.error + error * o.maxAbs + error * o.error)

  def scale(k: Double): Bounded = Bounded(maxAbs * math.abs(k), error * math.abs(k))

  /** After dropping bits to `lsb` with `rounding`. */
  def rounded(lsb: Double, rounding: Rounding): Bounded = copy(error = error + Rounding.maxErrorLsb(rounding) * lsb)

  /** The narrowest format with `fracBits` fraction bits that holds every computed value. */
  def format(fracBits: Int): FixedFormat = FixedFormat.forRange(computedMaxAbs, fracBits)
}

object Bounded {
  def exact(maxAbs: Double): Bounded = Bounded(maxAbs, 0.0)

  /** A constant `k` represented as `quantized`. */
  def constant(k: Double, quantized: Double): Bounded = Bounded(math.abs(k), math.abs(k - quantized))
}
