package reducerload.robot

/**
 * The paper's planar arm as a serial chain: three revolute joints about z, link i along its joint's x axis, a
 * point mass m3 at the end of link 3 and no other body, gravity along +x (so t1 = 0 points link 1 down and
 * the gravity term is +m3 g l3 sin(t1+t2+t3), as in docs/equations.md). Its frames for a payload: `link3`
 * (joint 3's frame) and `tip` (the end of link 3, where m3 sits).
 */
object Planar3 {
  val name: String = "planar3"

  def chain(r: RobotParams = RobotParams()): SerialChain = {
    val z = Vec3(0, 0, 1)
    def at(x: Double) = Transform(Mat3.identity, Vec3(x, 0, 0))
    SerialChain(
      name,
      IndexedSeq(
        ChainJoint("joint1", JointKind.Revolute, Transform.identity, z, RigidBody.massless),
        ChainJoint("joint2", JointKind.Revolute, at(r.l1), z, RigidBody.massless),
        ChainJoint("joint3", JointKind.Revolute, at(r.l2), z, RigidBody.pointMass(r.m3, Vec3(r.l3, 0, 0)))
      ),
      gravity = Vec3(r.g, 0, 0),
      tipFrames = Map("link3" -> Transform.identity, "tip" -> at(r.l3)),
      tip = "tip"
    )
  }
}
