package reducerload.load

/** Which formula the datapath computes. */
sealed abstract class LoadModel(val name: String, val description: String) {

  /** Weight of dd2 in the cos(t3) term: (dd1 + k dd2), for the joint-3 closed forms. */
  def dd2Weight: Int

  /**
   * A closed form of the planar arm's joint-3 load (one output), or every joint torque of any arm (rnea);
   * both run on [[reducerload.arm.ArmDatapath]].
   */
  def closedForm: Boolean = true

  override def toString: String = name
}

object LoadModel {

  /** tau3 of docs/equations.md, confirmed by Euler-Lagrange and Pinocchio's RNEA: (dd1 + dd2) cos t3. */
  case object Exact extends LoadModel("exact", "exact inverse dynamics (tau3 of docs/equations.md)") {
    val dd2Weight = 1
  }

  /** The paper's equation (6) as published: (dd1 + 2 dd2) cos t3, off by m3 l2 l3 dd2 cos t3. */
  case object PaperEq6 extends LoadModel("paper", "the paper's equation (6) as published") {
    val dd2Weight = 2
  }

  /** Every joint of any serial arm (the built-in planar3 or a URDF) by RNEA, as an expression graph. */
  case object Rnea extends LoadModel("rnea", "every joint torque by RNEA (the built-in planar3 or a URDF)") {
    val dd2Weight = 1
    override def closedForm = false
  }

  val all: Seq[LoadModel] = Seq(Exact, PaperEq6, Rnea)
  def parse(s: String): Option[LoadModel] = all.find(_.name == s)
}

/**
 * The joint-3 trace columns: angles t1..t3 (rad), velocities d1..d3 (rad/s), accelerations dd1..dd3
 * (rad/s^2); a row is one sample of planar3.
 */
object Joint3Columns {
  val names: Seq[String] = Seq("t1", "t2", "t3", "d1", "d2", "d3", "dd1", "dd2", "dd3")
}
