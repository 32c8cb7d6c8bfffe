package reducerload.load

/** Which formula the datapath computes. */
sealed abstract class LoadModel(val name: String, val description: String) {

  /** Weight of dd2 in the cos(t3) term: (dd1 + k dd2), for the joint-3 closed forms. */
  def dd2Weight: Int

  /** A closed form of the planar arm's joint-3 load ([[LoadDatapath]]), or every joint of any arm ([[reducerload.arm.ArmDatapath]]). */
  def closedForm: Boolean = true

  override def toString: String = name
}

object LoadModel {

  /** SPEC.md's tau3, confirmed by Euler-Lagrange and Pinocchio's RNEA: (dd1 + dd2) cos t3. */
  case object Exact extends LoadModel("exact", "exact inverse dynamics (SPEC.md tau3)") { val dd2Weight = 1 }

  /** The paper's equation (6) as published: (dd1 + 2 dd2) cos t3, off by m3 l2 l3 dd2 cos t3. */
  case object PaperEq6 extends LoadModel("paper", "the paper's equation (6) as published") { val dd2Weight = 2 }

  /** Every joint of any serial arm (the built-in planar3 or a URDF) by RNEA, as an expression graph. */
  case object Rnea extends LoadModel("rnea", "every joint torque by RNEA (the built-in planar3 or a URDF)") {
    val dd2Weight = 1
    override def closedForm = false
  }

  val all: Seq[LoadModel] = Seq(Exact, PaperEq6, Rnea)
  def parse(s: String): Option[LoadModel] = all.find(_.name == s)
}

/** One sample of joint state, in SI units (rad, rad/s, rad/s^2). */
final case class JointSample(t1: Double, t2: Double, t3: Double, d1: Double, d2: Double, d3: Double, dd1: Double, dd2: Double, dd3: Double) {
  def toSeq: Seq[Double] = Seq(t1, t2, t3, d1, d2, d3, dd1, dd2, dd3)
}

object JointSample {
  val columns: Seq[String] = Seq("t1", "t2", "t3", "d1", "d2", "d3", "dd1", "dd2", "dd3")
  def fromSeq(v: Seq[Double]): JointSample = {
    require(v.size == 9, s"JointSample needs 9 values, got ${v.size}")
    JointSample(v(0), v(1), v(2), v(3), v(4), v(5), v(6), v(7), v(8))
  }
}

/** Double-precision reference of both formulas. */
object LoadReference {
  def torque(r: RobotParams, model: LoadModel, s: JointSample): Double = {
    import s._
    val t23 = t2 + t3
    val t123 = t1 + t2 + t3
    r.a * dd1 * math.cos(t23) +
      r.b * (dd1 + model.dd2Weight * dd2) * math.cos(t3) +
      r.a * d1 * d1 * math.sin(t23) +
      r.b * (d1 + d2) * (d1 + d2) * math.sin(t3) +
      r.c * (dd1 + dd2 + dd3) +
      r.d * math.sin(t123)
  }
}
