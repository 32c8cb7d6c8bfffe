package reducerload.sim

import scala.collection.immutable.ArraySeq

import reducerload.fixedpoint.FixedFormat
import reducerload.load.{JointSample, LoadDatapath, LoadDatapathModel, LoadInputCodes, LoadOutputCodes, LoadParams, LoadReference}

/** The joint-3 `LoadDatapath` (models exact and paper) as `run simulate` replays it: `idx,load_hw,load_ref,error,out_of_range`. */
final class LoadReplay(val p: LoadParams) extends ReplayDesign[LoadInputCodes, LoadOutputCodes] {
  require(p.model.closedForm, s"LoadReplay: model ${p.model.name} is not a joint-3 closed form")
  private val model = new LoadDatapathModel(p)
  /** The model in long arithmetic when the formats allow (tested equal to `model`). */
  private val fast = if (FastLoadModel.supports(p)) Some(new FastLoadModel(p)) else None
  private val angleFormat = FastFixed.angleFormat(p.angleBits)

  val columns: Seq[String] = JointSample.columns
  val limits: Seq[(Int, Double)] = {
    val ranged = Seq("d1", "d2", "d3", "dd1", "dd2", "dd3").map(columns.indexOf)
    ranged.zip(p.robot.maxVelocity ++ p.robot.maxAcceleration)
  }

  /** `model.encode` of the row's sample, in fast exact arithmetic (tested equal). */
  def encode(row: IndexedSeq[Double]): LoadInputCodes = {
    def angle(x: Double) = FastFixed.angleCode(x, angleFormat)
    def codes(at: Int, formats: Array[FixedFormat]) = ArraySeq.unsafeWrapArray(Array.tabulate[BigInt](3)(j => FastFixed.codeHalfUp(row(at + j), formats(j))))
    LoadInputCodes(angle(row(0)), angle(row(1)), angle(row(2)), codes(3, velocityFormats), codes(6, accelerationFormats))
  }
  private val velocityFormats = p.velocityFormats.toArray
  private val accelerationFormats = p.accelerationFormats.toArray
  def evaluate(in: LoadInputCodes): LoadOutputCodes = fast.fold(model.evaluate(in))(_.evaluate(in))

  lazy val ports: HarnessPorts = LoadHarnessPorts(p)
  def harnessValues(in: LoadInputCodes): Seq[BigInt] = LoadHarnessPorts.values(in)
  def fromHarness(values: IndexedSeq[BigInt]): LoadOutputCodes = LoadHarnessPorts.codes(values)

  def samplePeriod: Int = p.samplePeriod
  def latency: Int = LoadDatapath.latency(p)

  val outputHeader = "idx,load_hw,load_ref,error,out_of_range"
  def result(index: Long, row: IndexedSeq[Double], out: LoadOutputCodes, text: java.lang.StringBuilder, errors: Array[Double]): Boolean = {
    val hw = FastFixed.toDouble(out.load, p.outputFormat.fracBits) // model.loadOf, fast
    val ref = LoadReference.torque(p.robot, p.model, JointSample.fromSeq(row))
    // StringBuilder.append(double) writes Double.toString's text
    text.append(index).append(',').append(hw).append(',').append(ref).append(',').append(hw - ref).append(',').append(if (out.outOfRange) '1' else '0')
    errors(0) = math.abs(hw - ref)
    out.outOfRange
  }

  val errorLabels: IndexedSeq[String] = IndexedSeq("joint 3 load")
  def errorBounds: IndexedSeq[Double] = IndexedSeq(p.errorBound)
  def description: String = s"model ${p.model.name}"
  def throughput: String = reducerload.app.Report.throughput(p)
}
