package reducerload.sim.replay

import reducerload.arm.{ArmIO, ArmModel, ArmOutputCodes, ArmParams, ArmSample, LoadReference, PayloadColumns}
import reducerload.config.LoadParams
import reducerload.dynamics.Rnea
import reducerload.graph.{SampleCodes, Signal}
import reducerload.monitor.{MonitorParams, MonitoredArmIO}
import reducerload.robot.RigidBody
import reducerload.sim.model.{FastArmModel, FastFixed, ReferenceTape}
import reducerload.sim.rtl.{ArmHarnessPorts, HarnessPorts}
import reducerload.sim.text.{DoubleText, FixedDecimal}

/**
 * Every joint of an arm (`ArmDatapath`, or `MonitoredArm` with `monitor`, model rnea) as `run simulate`
 * replays it: columns q1..qN,qd1..qdN,qdd1..qddN (then the ten [[PayloadColumns]] with a run-time payload),
 * result `idx,tau1_hw,tau1_ref,tau1_error,...,out_of_range`. [[LoadReplay]] changes the columns and the
 * reference for the joint-3 closed forms.
 */
class ArmReplay(val p: ArmParams, monitor: Option[MonitorParams] = None)
    extends ReplayDesign[SampleCodes, ArmOutputCodes] {
  private val model = new ArmModel(p)

  /** The model in long arithmetic when the formats allow (tested equal to `model`). */
  private val fast = if (FastArmModel.supports(p)) Some(new FastArmModel(p)) else None
  protected val joints: Int = p.chain.size
  private val angleFormat = FastFixed.angleFormat(p.numerics.angleBits)

  def layout: ReplayColumns = ReplayColumns.arm(joints, p.payload.isDefined)
  val limits: Seq[(Int, Double)] =
    (0 until joints).map(j => (joints + j, p.numerics.velocityLimits(j))) ++
      (0 until joints).map(j => (2 * joints + j, p.numerics.accelerationLimits(j)))

  protected def sample(row: IndexedSeq[Double]): ArmSample = ArmSample.fromRow(row.take(3 * joints))

  /** The payload of a row (its payload columns), when the design has one. */
  private def payload(row: IndexedSeq[Double]): Option[RigidBody] =
    Option.when(p.payload.isDefined)(
      PayloadColumns.body(row.slice(3 * joints, 3 * joints + PayloadColumns.names.size))
    )

  /** `model.encode(sample, payload)` of the row, in fast exact arithmetic (tested equal). */
  def encode(row: IndexedSeq[Double]): SampleCodes = {
    val n = p.numerics
    SampleCodes(
      (0 until joints).map(j => FastFixed.angleCode(row(j), angleFormat)),
      (0 until joints).map(j => FastFixed.codeHalfUp(row(joints + j), n.velocityPortFormat)),
      (0 until joints).map(j => FastFixed.codeHalfUp(row(2 * joints + j), n.accelerationPortFormat)),
      // A run-time gravity replays at its reset value, the chain's gravity (the reference's too).
      (p.payload.zip(payload(row)).fold(Map.empty[Signal.Parameter, Double]) { case (spec, body) =>
        spec.values(p.chain, body)
      } ++ p.gravity.fold(Map.empty[Signal.Parameter, Double])(_.values(p.chain.gravity))).map {
        case (s, v) =>
          s -> FastFixed.codeHalfUp(v, n.parameterFormats(s))
      }
    )
  }
  def evaluate(in: SampleCodes): ArmOutputCodes = fast.fold(model.evaluate(in))(_.evaluate(in))

  lazy val ports: HarnessPorts =
    ArmHarnessPorts(monitor.fold(new ArmIO(p))(m => new MonitoredArmIO(p, m)))
  def harnessValues(in: SampleCodes): Seq[BigInt] =
    ArmHarnessPorts.values(in) ++ p.numerics.parameters.map(in.parameters)
  def fromHarness(values: IndexedSeq[BigInt]): ArmOutputCodes =
    ArmHarnessPorts.codes(values, p.graph.outputs.size)

  def samplePeriod: Int = p.schedule.clocksPerSample
  def latency: Int = p.latency

  def outputHeader: String =
    ("idx" +: (1 to joints).flatMap(j =>
      Seq(s"tau${j}_hw", s"tau${j}_ref", s"tau${j}_error")
    ) :+ "out_of_range").mkString(",")

  def result(
      index: Long,
      row: IndexedSeq[Double],
      out: ArmOutputCodes,
      text: java.lang.StringBuilder,
      errors: Array[Double]
  ): Boolean = {
    val s = sample(row)
    val hw = out.tau.map(FastFixed.toDouble(_, p.analysis.outputPortFormat.fracBits)) // model.torques, fast
    // With a payload: RNEA on the chain whose last body carries the row's payload.
    val chain = p.payload.zip(payload(row)).fold(p.chain) { case (spec, body) => spec.merged(p.chain, body) }
    val ref = Rnea.reference(chain, s.q, s.qd, s.qdd)
    val outOfRange = out.outOfRange.exists(identity)
    text.append(index)
    // The hardware's value as its exact decimal (FixedDecimal), the reference and the error by DoubleText
    (0 until joints).foreach { j =>
      FixedDecimal.append(text.append(','), out.tau(j), p.analysis.outputPortFormat.fracBits)
      DoubleText.append(DoubleText.append(text.append(','), ref(j)).append(','), hw(j) - ref(j))
      errors(j) = math.abs(hw(j) - ref(j))
    }
    text.append(',').append(if (outOfRange) '1' else '0')
    outOfRange
  }

  /** The reference as a tape (bit-identical to [[result]]'s, see ReplayArraysSpec). */
  protected def referenceTape(): ReferenceTape = ReferenceTape.rnea(p.chain)

  // With a payload, the general path (the arrays' reference tape has no payload inputs).
  override lazy val arrays: Option[ArrayReplay] = fast.filter(_ => p.payload.isEmpty).map { model =>
    val reference = referenceTape()
    require(
      reference.outputs == model.torques,
      s"ArmReplay: ${reference.outputs} reference torques for ${model.torques} outputs"
    )
    new ArrayReplay {
      def inputCount: Int = model.inputCount
      def outputCount: Int = model.outputCount
      def worker(): ArrayReplay.Worker = new ArmWorker(model, reference)
    }
  }

  private final class ArmWorker(model: FastArmModel, reference: ReferenceTape) extends ArrayReplay.Worker {
    private val runner = model.runner()
    private val v = reference.tape.scratch()
    private val n = joints
    private val torques = model.torques
    private val outFrac = p.analysis.outputPortFormat.fracBits
    private val (velocity, acceleration) = (p.numerics.velocityPortFormat, p.numerics.accelerationPortFormat)
    private val (vMin, vMax) = (FastFixed.minOf(velocity), FastFixed.maxOf(velocity))
    private val (aMin, aMax) = (FastFixed.minOf(acceleration), FastFixed.maxOf(acceleration))

    def encode(rows: Array[Double], row: Int, codes: Array[Long], at: Int): Unit = {
      var j = 0
      while (j < n) {
        codes(at + j) = FastFixed.angleCodeLong(rows(row + j), angleFormat)
        codes(at + n + j) = FastFixed.codeHalfUpLong(rows(row + n + j), velocity, vMin, vMax)
        codes(at + 2 * n + j) = FastFixed.codeHalfUpLong(rows(row + 2 * n + j), acceleration, aMin, aMax)
        j += 1
      }
    }

    def evaluate(codes: Array[Long], at: Int, out: Array[Long], outAt: Int): Unit =
      runner.evaluate(codes, at, out, outAt)

    def result(
        index: Long,
        rows: Array[Double],
        row: Int,
        out: Array[Long],
        outAt: Int,
        text: java.lang.StringBuilder,
        errors: Array[Double]
    ): Boolean = {
      val v = this.v
      reference.evaluate(rows, row, v)
      text.append(index)
      var k = 0
      while (k < torques) {
        val code = out(outAt + k)
        val hw = FastFixed.longToDouble(code, outFrac)
        val ref = reference.tape.output(v, k)
        FixedDecimal.append(text.append(','), code, outFrac)
        DoubleText.append(DoubleText.append(text.append(','), ref).append(','), hw - ref)
        errors(k) = math.abs(hw - ref)
        k += 1
      }
      var flagged = false
      var j = 0
      while (j < n) { if (out(outAt + torques + j) != 0) flagged = true; j += 1 }
      text.append(',').append(if (flagged) '1' else '0')
      flagged
    }
  }

  def errorLabels: IndexedSeq[String] = p.jointNames
  def errorBounds: IndexedSeq[Double] = p.errorBounds
  def description: String = s"robot ${p.chain.name} ($joints joints), every joint by RNEA"
  def throughput: String =
    if (samplePeriod == 1) "one sample per clock" else s"one sample every $samplePeriod clocks"
}

/**
 * The joint-3 closed forms (models exact and paper) as `run simulate` replays them: the arm datapath of their
 * graph, with the joint-3 trace columns `t1,t2,t3,d1,d2,d3,dd1,dd2,dd3` (in the arm's q, qd, qdd order) and
 * the result `idx,load_hw,load_ref,error,out_of_range`.
 */
final class LoadReplay(settings: LoadParams, arm: ArmParams) extends ArmReplay(arm) {
  require(settings.model.closedForm, s"LoadReplay: model ${settings.model.name} is not a joint-3 closed form")

  override def layout: ReplayColumns = ReplayColumns.joint3

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
