package reducerload.cordic

import reducerload.sim.rtl.{Cycle, Stream}

import scala.util.Random

/** Stimulus and golden checks for the CORDIC unit, in plain Scala (no simulator calls). */
object CordicChecks {

  /** Max |error| of (cos, sin) codes against double precision at each code's exact angle. */
  def maxError(p: CordicParams, results: Iterable[(BigInt, (BigInt, BigInt))]): Double = {
    val model = new CordicModel(p)
    results.iterator
      .map { case (code, (c, s)) =>
        val theta = model.angleOf(code)
        math.max(
          math.abs(p.outputFormat.toDouble(c) - math.cos(theta)),
          math.abs(p.outputFormat.toDouble(s) - math.sin(theta))
        )
      }
      .maxOption
      .getOrElse(0.0)
  }

  /** Angles just either side of every quadrant boundary, in an order that crosses quadrants every cycle. */
  def quadrantCrossers(p: CordicParams): IndexedSeq[BigInt] = {
    val full = BigInt(1) << p.angleBits
    val quarter = full >> 2
    for {
      delta <- IndexedSeq(-2, -1, 0, 1, 2)
      q <- 0 until 4
    } yield ((quarter * q + delta) % full + full) % full
  }

  def randomAngles(p: CordicParams, rng: Random, n: Int): IndexedSeq[BigInt] =
    IndexedSeq.fill(n)(BigInt(p.angleBits, rng.self))

  /** Stream with bubbles and resets, flushed with `latency` bubbles at the end. */
  def stimulus(
      p: CordicParams,
      angles: IndexedSeq[BigInt],
      rng: Random,
      resets: Int
  ): IndexedSeq[Cycle[BigInt]] =
    Stream.randomStimulus(rng, angles, bubble = 0.1, resets = resets) ++ IndexedSeq.fill(p.latency + 2)(
      Cycle.Bubble
    )

  /** Check a simulated stream: timing and bits against the model, error against double precision. */
  final case class Verdict(mismatches: Seq[String], checked: Int, maxError: Double)

  def check(
      p: CordicParams,
      stim: IndexedSeq[Cycle[BigInt]],
      observed: IndexedSeq[Option[(BigInt, BigInt)]]
  ): Verdict = {
    val model = new CordicModel(p)
    val expectedCodes = Stream.expected(stim, p.latency)
    val expected = expectedCodes.map(_.map(code => model.sinCosRaw(code)))
    val bad = Stream.mismatches[(BigInt, BigInt), (BigInt, BigInt)](expected, observed, _ == _)
    val pairs = expectedCodes.zip(observed).collect { case (Some(code), Some(out)) => code -> out }
    Verdict(bad, pairs.size, maxError(p, pairs))
  }
}
