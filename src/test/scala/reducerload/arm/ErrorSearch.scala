package reducerload.arm

import reducerload.app.Cli
import reducerload.util.InputError

/**
 * An adversarial search for a design's largest torque error against its graph in double precision, beside the
 * bound the analysis derives for each joint: a benchmark, and in short a test ([[ErrorSearchSpec]]). Random
 * samples (angles anywhere; velocities and accelerations within their limits, half of the samples with each
 * at a limit, where ranges and so errors are largest), then for each joint a climb from its worst sample by
 * seeded Gaussian steps, a step kept when that joint's error grows. What the search finds bounds the worst
 * case from below, the analysis from above: their ratio is the most a tighter (still sound) analysis could
 * narrow the words the target-error fit chooses.
 *
 * {{{
 * ./sbt "Test/runMain reducerload.arm.ErrorSearch --seed 81 --samples 3000 --climbs 1500 --robot
 *   golden/robots/ur5_robot.urdf --tip tool0 --max-acceleration 15 --target-error 1e-3"
 * }}}
 *
 * The search's own flags may stand anywhere on the line; the rest are a design as `run emit` takes it.
 */
object ErrorSearch {

  /** A joint's largest error found, its derived bound (N·m) and the sample it was found at. */
  final case class Found(error: Double, bound: Double, sample: ArmSample)

  /** Inside the limits: a sample at a limit could round past it and be clamped (and flagged). */
  private val inside = 0.9999

  def apply(p: ArmParams, seed: Long, samples: Int, climbs: Int): IndexedSeq[Found] = {
    require(samples > 0 && climbs >= 0, s"ErrorSearch: $samples samples and $climbs climbs")
    val model = new ArmModel(p)
    val joints = p.chain.size
    val limits =
      Seq(p.numerics.velocityLimits, p.numerics.accelerationLimits).map(_.map(_ * inside).toIndexedSeq)
    val rng = new scala.util.Random(seed)
    def errors(s: ArmSample): IndexedSeq[Double] =
      model.evaluate(s).zip(model.reference(s)).map { case (a, b) => math.abs(a - b) }
    def angles = IndexedSeq.fill(joints)(rng.between(-math.Pi, math.Pi))
    def within(l: IndexedSeq[Double]) = l.map(x => rng.between(-x, x))
    def atLimits(l: IndexedSeq[Double]) = l.map(x => if (rng.nextBoolean()) x else -x)
    val drawn = (0 until samples).map { i =>
      val s =
        if (i % 2 == 0) ArmSample(angles, within(limits(0)), within(limits(1)))
        else ArmSample(angles, atLimits(limits(0)), atLimits(limits(1)))
      (s, errors(s))
    }
    (0 until joints).map { j =>
      val start = drawn.maxBy(_._2(j))
      // steps of 5 % of each range, then of 0.2 %: first across the neighbourhood, then into its peak
      val (sample, error) = (0 until climbs).foldLeft((start._1, start._2(j))) { case ((s, e), k) =>
        val scale = if (k < climbs / 3) 0.05 else 0.002
        def step(v: IndexedSeq[Double], range: IndexedSeq[Double]) =
          v.zip(range).map { case (x, r) => (x + rng.nextGaussian() * scale * r).max(-r).min(r) }
        val next = ArmSample(
          s.q.map(_ + rng.nextGaussian() * scale * math.Pi),
          step(s.qd, limits(0)),
          step(s.qdd, limits(1))
        )
        val found = errors(next)(j)
        if (found > e) (next, found) else (s, e)
      }
      Found(error, p.analysis.outputs(j).errorBound, sample)
    }
  }

  def main(args: Array[String]): Unit = {
    def refuse(message: String): Nothing = {
      System.err.println(s"error: command line: $message")
      sys.exit(2)
    }
    def flag(name: String, default: Long, least: Long, most: Long): Long = args.indexOf(name) match {
      case -1 => default
      case i =>
        args
          .lift(i + 1)
          .flatMap(_.toLongOption)
          .filter(v => v >= least && v <= most)
          .getOrElse(refuse(s"$name takes a whole number from $least to $most"))
    }
    def count(name: String, default: Int, least: Int): Int = flag(name, default, least, Int.MaxValue).toInt
    val own = Set("--seed", "--samples", "--climbs")
    val (seed, samples, climbs) =
      (
        flag("--seed", 1, Long.MinValue, Long.MaxValue),
        count("--samples", 3000, 1),
        count("--climbs", 1500, 0)
      )
    val design = args.indices.filterNot(i => own(args(i)) || (i > 0 && own(args(i - 1)))).map(args(_))
    val p =
      try Cli.parse("emit", design, Nil).compiled.arm
      catch {
        case e @ (_: InputError | _: IllegalArgumentException) =>
          System.err.println(s"error: ${e.getMessage.stripPrefix("requirement failed: ")}")
          sys.exit(2)
      }
    println(s"seed $seed, $samples samples, $climbs climbs per joint")
    println()
    println("| joint | derived bound (N·m) | largest error found | found / bound |")
    println("| --- | --- | --- | --- |")
    ErrorSearch(p, seed, samples, climbs).zipWithIndex.foreach { case (f, j) =>
      println(f"| ${j + 1} | ${f.bound}%.3e | ${f.error}%.3e | ${f.error / f.bound}%.2f |")
    }
  }
}
