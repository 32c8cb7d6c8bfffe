package reducerload.dynamics

import reducerload.robot.{JointKind, Mat3, RigidBody, SerialChain, Transform, Vec3}

/**
 * An independent formulation of inverse dynamics, for tests: Euler-Lagrange with the mass matrix from
 * geometric Jacobians, tau = M(q) qdd + dM/dt qd - 1/2 d(qd' M qd)/dq - sum m_j g . dp_j/dq, dM/dq by central
 * differences. Shares nothing with [[Rnea]] but the robot description. Each joint may move several bodies
 * (`bodies`, in its frame), each summed on its own: the URDF tests give every link separately, so that the
 * reader's merging of the links fixed to a joint is checked too.
 */
object LagrangeReference {
  private final case class Frames(
      origins: IndexedSeq[Vec3],
      axes: IndexedSeq[Vec3],
      poses: IndexedSeq[Transform]
  )

  private def kinematics(chain: SerialChain, q: Seq[Double]): Frames = {
    val poses = chain.joints.indices
      .scanLeft(Transform.identity) { (parent, j) =>
        val joint = chain.joints(j)
        val motion =
          if (joint.kind == JointKind.Prismatic) Transform(Mat3.identity, joint.axis * q(j))
          else Transform(Mat3.axisAngle(joint.axis, q(j)), Vec3.zero)
        parent.compose(joint.origin).compose(motion)
      }
      .tail
    Frames(
      poses.map(_.translation),
      poses.zip(chain.joints).map { case (t, j) => t.rotation * j.axis },
      poses
    )
  }

  /** Jacobian columns (linear at the body's centre of mass, angular) of `body`, moved by joint j. */
  private def jacobian(
      f: Frames,
      chain: SerialChain,
      j: Int,
      body: RigidBody
  ): (IndexedSeq[Vec3], IndexedSeq[Vec3]) = {
    val c = f.poses(j)(body.com)
    chain.joints.indices.map { k =>
      if (k > j) (Vec3.zero, Vec3.zero)
      else if (chain.joints(k).kind == JointKind.Prismatic) (f.axes(k), Vec3.zero)
      else (f.axes(k).cross(c - f.origins(k)), f.axes(k))
    }.unzip
  }

  private def ownBodies(chain: SerialChain): IndexedSeq[Seq[RigidBody]] = chain.joints.map(j => Seq(j.body))

  def massMatrix(chain: SerialChain, q: Seq[Double]): IndexedSeq[IndexedSeq[Double]] =
    massMatrix(chain, ownBodies(chain), q)

  private def massMatrix(
      chain: SerialChain,
      bodies: IndexedSeq[Seq[RigidBody]],
      q: Seq[Double]
  ): IndexedSeq[IndexedSeq[Double]] = {
    val f = kinematics(chain, q)
    val n = chain.size
    val parts = chain.joints.indices.flatMap(j => bodies(j).map(j -> _)).map { case (j, body) =>
      val (jv, jw) = jacobian(f, chain, j, body)
      val r = f.poses(j).rotation
      val inertia = r * body.inertia * r.transpose
      IndexedSeq.tabulate(n, n)((a, b) => body.mass * jv(a).dot(jv(b)) + jw(a).dot(inertia * jw(b)))
    }
    IndexedSeq.tabulate(n, n)((a, b) => parts.map(_(a)(b)).sum)
  }

  def torques(
      chain: SerialChain,
      q: Seq[Double],
      qd: Seq[Double],
      qdd: Seq[Double],
      h: Double = 1e-6
  ): IndexedSeq[Double] = torques(chain, ownBodies(chain), q, qd, qdd, h)

  /** As above, joint j moving every body of `bodies(j)` (the chain's own bodies are not used). */
  def torques(
      chain: SerialChain,
      bodies: IndexedSeq[Seq[RigidBody]],
      q: Seq[Double],
      qd: Seq[Double],
      qdd: Seq[Double],
      h: Double
  ): IndexedSeq[Double] = {
    val n = chain.size
    val m = massMatrix(chain, bodies, q)
    val dM = (0 until n).map { k => // dM/dq_k
      val plus = massMatrix(chain, bodies, q.updated(k, q(k) + h))
      val minus = massMatrix(chain, bodies, q.updated(k, q(k) - h))
      IndexedSeq.tabulate(n, n)((a, b) => (plus(a)(b) - minus(a)(b)) / (2 * h))
    }
    val f = kinematics(chain, q)
    val gravity = (0 until n).map { i =>
      chain.joints.indices
        .flatMap(j => bodies(j).map(j -> _))
        .map { case (j, body) =>
          body.mass * chain.gravity.dot(jacobian(f, chain, j, body)._1(i))
        }
        .sum
    }
    (0 until n).map { i =>
      val inertial = (0 until n).map(k => m(i)(k) * qdd(k)).sum
      val mDot = (0 until n).map(k => (0 until n).map(l => dM(l)(i)(k) * qd(l)).sum * qd(k)).sum
      val dKdq = 0.5 * (0 until n).map(a => (0 until n).map(b => qd(a) * dM(i)(a)(b) * qd(b)).sum).sum
      inertial + mDot - dKdq - gravity(i)
    }
  }
}
