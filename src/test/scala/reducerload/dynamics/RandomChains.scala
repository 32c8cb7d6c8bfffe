package reducerload.dynamics

import reducerload.robot._

import scala.util.Random

/**
 * Seeded random serial arms for property tests: random axes (half of them axis-aligned), origins, masses and
 * inertias.
 */
object RandomChains {
  private def unit(rng: Random): Vec3 = {
    val v = Vec3(rng.nextGaussian(), rng.nextGaussian(), rng.nextGaussian())
    if (v.norm < 1e-3) Vec3(0, 0, 1) else v * (1 / v.norm)
  }

  private def axis(rng: Random): Vec3 =
    if (rng.nextBoolean()) unit(rng)
    else Seq(Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(0, -1, 0))(rng.nextInt(5))

  /**
   * A physical body: a solid box's principal moments (triangle inequality holds), turned by a random
   * rotation.
   */
  def body(rng: Random): RigidBody = {
    val m = 0.2 + 8 * rng.nextDouble()
    val Seq(a, b, c) = Seq.fill(3)(0.05 + 0.3 * rng.nextDouble())
    val principal = Mat3.diagonal(Vec3(b * b + c * c, a * a + c * c, a * a + b * b) * (m / 12))
    val r = Mat3.rpy(rng.nextDouble() * 6, rng.nextDouble() * 6, rng.nextDouble() * 6)
    RigidBody(
      m,
      Vec3(rng.nextDouble() - 0.5, rng.nextDouble() - 0.5, rng.nextDouble() - 0.5) * 0.4,
      r * principal * r.transpose
    )
  }

  def chain(rng: Random, joints: Int): SerialChain = SerialChain(
    s"random$joints",
    (0 until joints).map { j =>
      val rpy =
        if (rng.nextBoolean()) Mat3.rpy(math.Pi / 2 * rng.nextInt(4), 0, 0)
        else Mat3.rpy(rng.nextDouble() * 3, rng.nextDouble() * 3, rng.nextDouble() * 3)
      val origin =
        Transform(rpy, Vec3(rng.nextDouble() - 0.5, rng.nextDouble() - 0.5, rng.nextDouble() - 0.5) * 0.6)
      ChainJoint(s"j${j + 1}", JointKind.Revolute, origin, axis(rng), body(rng))
    },
    gravity = Vec3(0, 0, -9.81)
  )

  /**
   * A random arm with runs of parallel axes: each joint after the first, with even odds, turns about an axis
   * its fixed rotation carries onto its parent's ([[Rnea.parallelRuns]]).
   */
  def parallelChain(rng: Random, joints: Int): SerialChain = {
    val random = chain(rng, joints)
    val turned = random.joints.tail.foldLeft(Vector(random.joints.head)) { (done, j) =>
      if (rng.nextBoolean()) done :+ j
      else done :+ j.copy(axis = j.origin.rotation.transpose * done.last.axis)
    }
    random.copy(name = s"parallel$joints", joints = turned)
  }

  /** Angles anywhere on the circle, velocities and accelerations uniform within their limits. */
  def sample(
      rng: Random,
      vmax: Seq[Double],
      amax: Seq[Double]
  ): (IndexedSeq[Double], IndexedSeq[Double], IndexedSeq[Double]) = (
    vmax.indices.map(_ => (rng.nextDouble() * 2 - 1) * 2 * math.Pi),
    vmax.map(v => (rng.nextDouble() * 2 - 1) * v).toIndexedSeq,
    amax.map(a => (rng.nextDouble() * 2 - 1) * a).toIndexedSeq
  )
}
