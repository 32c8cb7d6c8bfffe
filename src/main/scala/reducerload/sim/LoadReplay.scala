package reducerload.sim

import reducerload.arm.{ArmOutputCodes, ArmParams, LoadReference}
import reducerload.config.LoadParams
import reducerload.load.Joint3Columns

/**
 * The joint-3 closed forms (models exact and paper) as `run simulate` replays them: the arm datapath of their
 * graph, with the joint-3 trace columns `t1,t2,t3,d1,d2,d3,dd1,dd2,dd3` (in the arm's q, qd, qdd order) and
 * the result `idx,load_hw,load_ref,error,out_of_range`.
 */
final class LoadReplay(settings: LoadParams, arm: ArmParams) extends ArmReplay(arm) {
  require(settings.model.closedForm, s"LoadReplay: model ${settings.model.name} is not a joint-3 closed form")

  override def columns: Seq[String] = Joint3Columns.names

  override def outputHeader: String = "idx,load_hw,load_ref,error,out_of_range"

  override def result(
      index: Long,
      row: IndexedSeq[Double],
      out: ArmOutputCodes,
      text: java.lang.StringBuilder,
      errors: Array[Double]
  ): Boolean = {
    val fracBits = p.analysis.outputPortFormat.fracBits
    val hw = FastFixed.toDouble(out.tau(0), fracBits) // ArmModel.torques, fast
    val ref = LoadReference.torque(settings.robot, settings.model, sample(row))
    val outOfRange = out.outOfRange.exists(identity)
    // The hardware's value as its exact decimal (FixedDecimal), the reference and the error by DoubleText
    FixedDecimal.append(text.append(index).append(','), out.tau(0), fracBits)
    DoubleText
      .append(DoubleText.append(text.append(','), ref).append(','), hw - ref)
      .append(',')
      .append(if (outOfRange) '1' else '0')
    errors(0) = math.abs(hw - ref)
    outOfRange
  }

  override protected def referenceTape(): ReferenceTape = ReferenceTape.joint3(settings.robot, settings.model)

  override def errorLabels: IndexedSeq[String] = IndexedSeq("joint 3 load")
  override def description: String = s"model ${settings.model.name}"
}
