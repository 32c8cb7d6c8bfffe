package reducerload.arm

/** Column names of an arm trajectory: q1..qn, qd1..qdn, qdd1..qddn (rad, rad/s, rad/s^2). */
object ArmTrajectory {
  def columns(joints: Int): Seq[String] =
    Seq("q", "qd", "qdd").flatMap(prefix => (1 to joints).map(j => s"$prefix$j"))
}
