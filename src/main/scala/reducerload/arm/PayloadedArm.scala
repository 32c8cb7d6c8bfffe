package reducerload.arm

import chisel3._
import chisel3.util._
import reducerload.fixedpoint.Rounding
import reducerload.graph.Signal
import reducerload.pipeline.MultiplierImpl

/** One sample's joint state: [[ArmInput]] without the payload, which comes from the payload registers. */
class JointSample(p: ArmParams) extends Bundle {
  val q = Vec(p.chain.size, UInt(p.numerics.angleBits.W))
  val qd = Vec(p.chain.size, SInt(p.numerics.velocityPortFormat.width.W))
  val qdd = Vec(p.chain.size, SInt(p.numerics.accelerationPortFormat.width.W))
}

/**
 * The host's side of the payload registers: `write` sets one staged parameter (`index` in
 * `numerics.parameters`' order: the payload's ten, then the run-time gravity's x, y, z; a code of the
 * parameter port format); `commit` makes the staged parameters the ones samples are computed with, from the
 * next sample on, and counts the sequence number up.
 */
class PayloadHostIO(p: ArmParams) extends Bundle {
  val write = Flipped(Valid(new Bundle {
    val index = UInt(log2Ceil(p.numerics.parameters.size).W)
    val value = SInt(p.numerics.parameterPortFormat.width.W)
  }))
  val commit = Input(Bool())
}

/** Torques, flags and the sequence number of the payload they were computed with. */
class PayloadedOutput(p: ArmParams) extends Bundle {
  val torques = new ArmOutput(p)
  val sequence = UInt(PayloadedArm.sequenceBits.W)
}

/**
 * [[ArmDatapath]] with host-written payload registers. The datapath takes a sample's payload with its joint
 * state, like qd, so a commit between two samples is at a sample boundary by construction: every sample is
 * computed with the payload committed when it was taken. The committed payload's sequence number (counted
 * modulo 2^sequenceBits from 0 at reset, when the payload is none and the gravity the elaboration one) leaves
 * beside its sample's torques, through a queue as deep as the samples in flight. Out-of-range parameters are
 * clamped and flagged by the datapath.
 */
class PayloadedArm(val p: ArmParams)(implicit multiplierImpl: MultiplierImpl) extends Module {
  require(p.numerics.parameters.nonEmpty, s"PayloadedArm: ${p.moduleName} has no run-time payload or gravity")
  override def desiredName = s"Payloaded${p.moduleName}"
  private val parameters = p.numerics.parameters.size
  val io = IO(new Bundle {
    val in = Flipped(Decoupled(new JointSample(p)))
    val host = new PayloadHostIO(p)
    val out = Valid(new PayloadedOutput(p))
  })

  private val staged = RegInit(
    VecInit(PayloadedArm.resetCodes(p).map(_.S(p.numerics.parameterPortFormat.width.W)))
  )
  private val active = RegInit(
    VecInit(PayloadedArm.resetCodes(p).map(_.S(p.numerics.parameterPortFormat.width.W)))
  )
  private val sequence = RegInit(0.U(PayloadedArm.sequenceBits.W))
  when(io.host.write.valid)(staged(io.host.write.bits.index) := io.host.write.bits.value)
  // The staged payload before this cycle's write: a write and a commit in one cycle commit the older value.
  when(io.host.commit) {
    active := staged
    sequence := sequence + 1.U
  }

  private val datapath = Module(new ArmDatapath(p))
  datapath.io.in.valid := io.in.valid
  io.in.ready := datapath.io.in.ready
  datapath.io.in.bits.q := io.in.bits.q
  datapath.io.in.bits.qd := io.in.bits.qd
  datapath.io.in.bits.qdd := io.in.bits.qdd
  datapath.io.in.bits.payload.get := active

  // Each taken sample's sequence number waits for its torques; at most this many samples are in flight.
  private val inFlight = p.latency / p.schedule.clocksPerSample + 2
  private val sequences = Module(new Queue(UInt(PayloadedArm.sequenceBits.W), inFlight))
  sequences.io.enq.valid := io.in.valid && datapath.io.in.ready
  sequences.io.enq.bits := sequence
  sequences.io.deq.ready := datapath.io.out.valid
  io.out.valid := datapath.io.out.valid
  io.out.bits.torques := datapath.io.out.bits
  io.out.bits.sequence := sequences.io.deq.bits
}

object PayloadedArm {

  /** Width of the payload sequence number. */
  val sequenceBits: Int = 8

  /**
   * The parameter registers' reset codes in `numerics.parameters`' order: no payload (every inertial
   * parameter 0), the chain's own gravity (folded with the mounting).
   */
  def resetCodes(p: ArmParams): IndexedSeq[BigInt] = p.numerics.parameters.map {
    case _: Signal.Inertial => BigInt(0)
    case g: Signal.Gravity =>
      p.numerics.parameterFormats(g).fromDouble(p.chain.gravity.toSeq(g.axis), Rounding.HalfUp)._1
  }
}
