package reducerload.robot

/** How a moving joint moves. (URDF `continuous` is a revolute joint without position limits.) */
sealed abstract class JointKind(val name: String) { override def toString: String = name }
object JointKind {
  case object Revolute extends JointKind("revolute")
  case object Continuous extends JointKind("continuous")
  case object Prismatic extends JointKind("prismatic")
  val all: Seq[JointKind] = Seq(Revolute, Continuous, Prismatic)
}

/**
 * Mass properties of one rigid body, in the frame of the joint that moves it.
 *
 * @param mass
 *   kg, >= 0 (0: a massless link)
 * @param com
 *   centre of mass, m
 * @param inertia
 *   rotational inertia about the centre of mass, kg m^2, in the joint frame's axes
 */
final case class RigidBody(mass: Double, com: Vec3, inertia: Mat3) {

  /** The same body seen from a parent frame in which this body's frame sits at `t`. */
  def transformed(t: Transform): RigidBody =
    RigidBody(mass, t(com), t.rotation * inertia * t.rotation.transpose)

  /**
   * Two bodies fixed to each other, both in this frame: masses add, the parallel-axis theorem moves the
   * inertias.
   */
  def merge(o: RigidBody): RigidBody = {
    val m = mass + o.mass
    if (m == 0) RigidBody.massless
    else {
      val c = (com * mass + o.com * o.mass) * (1 / m)
      def shifted(b: RigidBody) = { // inertia of b about c: I_b + m_b (|d|^2 E - d d^T), d = com_b - c
        val d = b.com - c
        b.inertia + (Mat3.identity.scale(d.dot(d)) - Mat3.tabulate((i, j) => d.toSeq(i) * d.toSeq(j)))
          .scale(b.mass)
      }
      RigidBody(m, c, shifted(this) + shifted(o))
    }
  }
}

object RigidBody {
  val massless: RigidBody = RigidBody(0.0, Vec3.zero, Mat3.zero)
  def pointMass(mass: Double, at: Vec3): RigidBody = RigidBody(mass, at, Mat3.zero)
}

/**
 * One moving joint of a serial chain and the body it moves (every link fixed to it merged in).
 *
 * @param name
 *   the URDF joint name (or a generated one for built-in robots)
 * @param kind
 *   revolute, continuous or prismatic
 * @param origin
 *   pose of this joint's frame at q = 0 in the previous moving joint's frame (the base for joint 1); fixed
 *   joints between the two are composed into it
 * @param axis
 *   unit axis in this joint's frame
 * @param body
 *   what this joint moves, in this joint's frame
 * @param velocityLimit
 *   URDF `<limit velocity>` (rad/s or m/s), when given
 * @param effortLimit
 *   URDF `<limit effort>` (N·m or N), when given
 */
final case class ChainJoint(
    name: String,
    kind: JointKind,
    origin: Transform,
    axis: Vec3,
    body: RigidBody,
    velocityLimit: Option[Double] = None,
    effortLimit: Option[Double] = None
)

/**
 * A serial chain of moving joints from the base to the tip, numbered 1..n from the base, with gravity in base
 * coordinates (m/s^2; Pinocchio's default is (0, 0, -9.81)).
 *
 * @param warnings
 *   what reading the robot's description accepted but a user should know (see [[reducerload.util.Warning]])
 * @param source
 *   the file it was read from (empty: built in)
 * @param tipFrames
 *   the links the last moving joint carries (its child link, links fixed to it, links of joints locked off
 *   the chain after it), each with its pose in that joint's frame: where a payload can be attached
 * @param tip
 *   the link the chain ends at, one of [[tipFrames]] (empty: none named)
 */
final case class SerialChain(
    name: String,
    joints: IndexedSeq[ChainJoint],
    gravity: Vec3,
    warnings: Seq[reducerload.util.Warning] = Nil,
    source: String = "",
    tipFrames: Map[String, Transform] = Map.empty,
    tip: String = ""
) {
  require(joints.nonEmpty, s"robot $name: the chain has no moving joint")
  require(joints.map(_.name).distinct.size == joints.size, s"robot $name: joint names repeat")
  joints.foreach { j =>
    require(
      math.abs(j.axis.norm - 1) < 1e-9,
      s"robot $name: joint ${j.name}: axis ${j.axis} is not a unit vector"
    )
    require(
      j.body.mass >= 0 && !j.body.mass.isNaN,
      s"robot $name: joint ${j.name}: negative mass ${j.body.mass}"
    )
  }
  require(
    tip.isEmpty || tipFrames.contains(tip),
    s"robot $name: the tip link '$tip' is not among the carried links"
  )
  def size: Int = joints.size

  /**
   * The same chain carrying `payload` (mass, centre of mass and inertia about it in the frame of the link
   * `frame`, one of [[tipFrames]]): merged into the last moving joint's body, as Pinocchio's
   * `model.inertias[last] += placement * payload` in the golden traces.
   */
  def carrying(frame: String, payload: RigidBody): SerialChain = {
    val pose = tipFrames.getOrElse(
      frame,
      throw new IllegalArgumentException(
        s"$label: '$frame' is not a link the last moving joint carries (${tipFrames.keys.toSeq.sorted.mkString(", ")})"
      )
    )
    val last = joints.last
    copy(joints = joints.updated(size - 1, last.copy(body = last.body.merge(payload.transformed(pose)))))
  }

  /** The same chain on a base mounted so: its gravity rotated into base coordinates (see [[Mounting]]). */
  def mounted(m: Mounting): SerialChain = if (m.isFloor) this else copy(gravity = m.gravity(gravity))

  /** Where a refusal about the robot points: its file, or its name when built in. */
  def label: String = if (source.nonEmpty) source else s"robot $name"
}
