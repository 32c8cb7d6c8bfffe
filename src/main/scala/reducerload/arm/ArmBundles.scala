package reducerload.arm

import chisel3._
import chisel3.util.{Decoupled, Valid}

/**
 * One sample: per joint a binary angle (full turn = 2^angleBits; any code is in range), a velocity and an
 * acceleration as raw codes of the port formats (every joint in the widest joint's format), and the payload
 * it is computed with.
 */
class ArmInput(p: ArmParams) extends Bundle {
  val q = Vec(p.chain.size, UInt(p.numerics.angleBits.W))
  val qd = Vec(p.chain.size, SInt(p.numerics.velocityPortFormat.width.W))
  val qdd = Vec(p.chain.size, SInt(p.numerics.accelerationPortFormat.width.W))

  /**
   * With a run-time payload or gravity: the codes of the run-time parameters this sample is computed with
   * (the payload's, then the gravity's), in `numerics.parameters`' order, every one in the widest parameter's
   * format (all have the same fraction bits); none otherwise.
   */
  val payload = Option.when(p.numerics.parameters.nonEmpty)(
    Vec(p.numerics.parameters.size, SInt(p.numerics.parameterPortFormat.width.W))
  )
}

/**
 * Every joint torque (N·m, raw codes of the output port format) and, per joint, whether its inputs were
 * beyond the declared ranges.
 */
class ArmOutput(p: ArmParams) extends Bundle {
  val tau = Vec(p.graph.outputs.size, SInt(p.analysis.outputPortFormat.width.W))
  val outOfRange = Vec(p.chain.size, Bool())
}

/** [[ArmDatapath]]'s ports: samples in (ready/valid), torques and flags out (valid). */
class ArmIO(p: ArmParams) extends Bundle {
  val in = Flipped(Decoupled(new ArmInput(p)))
  val out = Valid(new ArmOutput(p))
}
