package reducerload.robot

/** A 3-vector of doubles: robot constants (origins, axes, centres of mass) in SI units. */
final case class Vec3(x: Double, y: Double, z: Double) {
  def +(o: Vec3): Vec3 = Vec3(x + o.x, y + o.y, z + o.z)
  def -(o: Vec3): Vec3 = Vec3(x - o.x, y - o.y, z - o.z)
  def *(k: Double): Vec3 = Vec3(x * k, y * k, z * k)
  def dot(o: Vec3): Double = x * o.x + y * o.y + z * o.z
  def cross(o: Vec3): Vec3 = Vec3(y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x)
  def norm: Double = math.sqrt(dot(this))
  def toSeq: Seq[Double] = Seq(x, y, z)
  def isFinite: Boolean = toSeq.forall(v => !v.isNaN && !v.isInfinite)
}

object Vec3 {
  val zero: Vec3 = Vec3(0, 0, 0)
  def apply(s: Seq[Double]): Vec3 = {
    require(s.size == 3, s"Vec3 needs 3 values, got ${s.size}"); Vec3(s(0), s(1), s(2))
  }
}

/** A 3x3 matrix of doubles, row major: rotations and inertia tensors. */
final case class Mat3(rows: IndexedSeq[IndexedSeq[Double]]) {
  require(rows.size == 3 && rows.forall(_.size == 3), "Mat3 needs 3 rows of 3 values")
  def apply(i: Int, j: Int): Double = rows(i)(j)
  def *(v: Vec3): Vec3 = Vec3((0 until 3).map(i => rows(i)(0) * v.x + rows(i)(1) * v.y + rows(i)(2) * v.z))
  def *(o: Mat3): Mat3 = Mat3.tabulate((i, j) => (0 until 3).map(k => this(i, k) * o(k, j)).sum)
  def +(o: Mat3): Mat3 = Mat3.tabulate((i, j) => this(i, j) + o(i, j))
  def -(o: Mat3): Mat3 = Mat3.tabulate((i, j) => this(i, j) - o(i, j))
  def scale(k: Double): Mat3 = Mat3.tabulate((i, j) => this(i, j) * k)
  def transpose: Mat3 = Mat3.tabulate((i, j) => this(j, i))
  def isFinite: Boolean = rows.flatten.forall(v => !v.isNaN && !v.isInfinite)
}

object Mat3 {
  def tabulate(f: (Int, Int) => Double): Mat3 = Mat3(IndexedSeq.tabulate(3, 3)(f))
  val identity: Mat3 = tabulate((i, j) => if (i == j) 1.0 else 0.0)
  val zero: Mat3 = tabulate((_, _) => 0.0)
  def diagonal(d: Vec3): Mat3 = tabulate((i, j) => if (i != j) 0.0 else d.toSeq(i))

  /** Symmetric inertia tensor from URDF's six entries. */
  def symmetric(ixx: Double, ixy: Double, ixz: Double, iyy: Double, iyz: Double, izz: Double): Mat3 =
    Mat3(IndexedSeq(IndexedSeq(ixx, ixy, ixz), IndexedSeq(ixy, iyy, iyz), IndexedSeq(ixz, iyz, izz)))

  /** Skew matrix [v]x, so that [v]x w = v cross w. */
  def skew(v: Vec3): Mat3 = Mat3(
    IndexedSeq(IndexedSeq(0, -v.z, v.y), IndexedSeq(v.z, 0, -v.x), IndexedSeq(-v.y, v.x, 0))
  )

  /** URDF roll-pitch-yaw: fixed axes x, y, z in that order, R = Rz(yaw) Ry(pitch) Rx(roll). */
  def rpy(roll: Double, pitch: Double, yaw: Double): Mat3 = {
    def c(a: Double) = snap(math.cos(a))
    def s(a: Double) = snap(math.sin(a))
    val rx = Mat3(
      IndexedSeq(IndexedSeq(1, 0, 0), IndexedSeq(0, c(roll), -s(roll)), IndexedSeq(0, s(roll), c(roll)))
    )
    val ry = Mat3(
      IndexedSeq(IndexedSeq(c(pitch), 0, s(pitch)), IndexedSeq(0, 1, 0), IndexedSeq(-s(pitch), 0, c(pitch)))
    )
    val rz = Mat3(
      IndexedSeq(IndexedSeq(c(yaw), -s(yaw), 0), IndexedSeq(s(yaw), c(yaw), 0), IndexedSeq(0, 0, 1))
    )
    rz * ry * rx
  }

  /**
   * cos/sin of the angles URDFs write as decimals of pi/2 (1.5707963, 3.14159265) are 1e-8 away from 0 and
   * \+-1; rounded to them, the folded constants become exact zeros and ones and the multiplications they
   * would cost disappear. The change is far below any fixed-point LSB used.
   */
  val snapTolerance: Double = 1e-7
  def snap(v: Double): Double =
    if (math.abs(v) < snapTolerance) 0.0
    else if (math.abs(v - 1) < snapTolerance) 1.0
    else if (math.abs(v + 1) < snapTolerance) -1.0
    else v

  /** Rotation by `angle` about the unit `axis` (Rodrigues). */
  def axisAngle(axis: Vec3, angle: Double): Mat3 = {
    val k = skew(axis)
    identity + k.scale(math.sin(angle)) + (k * k).scale(1 - math.cos(angle))
  }
}

/**
 * A rigid transform: `rotation` maps child coordinates to parent coordinates, `translation` is the child
 * origin in the parent.
 */
final case class Transform(rotation: Mat3, translation: Vec3) {

  /** this * o: o's child frame expressed in this transform's parent frame. */
  def compose(o: Transform): Transform =
    Transform(rotation * o.rotation, rotation * o.translation + translation)
  def apply(p: Vec3): Vec3 = rotation * p + translation
}

object Transform {
  val identity: Transform = Transform(Mat3.identity, Vec3.zero)
}
