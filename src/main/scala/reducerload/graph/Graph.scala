package reducerload.graph

/** Index of a node in its [[Graph]]; operands always have smaller indices than their users. */
final case class NodeId(index: Int) extends AnyVal

/** A per-sample input of the datapath, by joint (0-based; reports number joints from 1). */
sealed abstract class Signal(val symbol: String) {
  def joint: Int
  override def toString: String = s"$symbol${joint + 1}"
}
object Signal {
  final case class Velocity(joint: Int) extends Signal("qd")
  final case class Acceleration(joint: Int) extends Signal("qdd")

  /**
   * A run-time parameter of the model: an input like qd, held for a whole sample, within a declared interval
   * ([[Numerics]]), so that one design serves every value in the declared set. Host-written and committed at
   * a sample boundary in hardware.
   */
  sealed abstract class Parameter(symbol: String) extends Signal(symbol)

  /**
   * A run-time inertial parameter of a body joint `joint` carries beside its constant one (the payload on the
   * last joint).
   */
  final case class Inertial(joint: Int, parameter: InertialParameter) extends Parameter(parameter.symbol) {
    override def toString: String = s"${parameter.symbol}@${joint + 1}"
  }

  /**
   * One component of the gravity vector in base coordinates (m/s^2; arms on moving platforms): the base's
   * acceleration, which enters the dynamics at the first joint (its `joint`).
   */
  final case class Gravity(axis: Int) extends Parameter("g" + "xyz" (axis)) {
    require(axis >= 0 && axis < 3, s"Signal.Gravity: axis $axis is not 0, 1 or 2")
    def joint: Int = 0
    override def toString: String = symbol
  }

  /** The three gravity components, x, y, z. */
  val gravity: IndexedSeq[Gravity] = (0 until 3).map(Gravity(_))

  /** The ten run-time parameters of the body joint `joint` carries, in [[InertialParameter.all]]'s order. */
  def inertial(joint: Int): IndexedSeq[Inertial] = InertialParameter.all.map(Inertial(joint, _))
}

/**
 * One of a rigid body's ten inertial parameters in its own frame, as robot controllers state load data: the
 * mass (kg), the centre of mass (m) and the inertia about the centre of mass (kg m^2, upper triangle).
 */
sealed abstract class InertialParameter(val symbol: String) { override def toString: String = symbol }
object InertialParameter {
  case object Mass extends InertialParameter("mass")
  final case class Com(axis: Int) extends InertialParameter("c" + "xyz" (axis))
  final case class Inertia(row: Int, col: Int) extends InertialParameter("i" + "xyz" (row) + "xyz" (col)) {
    require(row <= col, s"InertialParameter: inertia ($row, $col) is below the diagonal")
    def diagonal: Boolean = row == col
  }

  /** Mass, cx, cy, cz, ixx, ixy, ixz, iyy, iyz, izz: the order of the payload columns and ports. */
  val all: IndexedSeq[InertialParameter] =
    Mass +: ((0 until 3).map(Com(_)) ++ (for (r <- 0 until 3; c <- r until 3) yield Inertia(r, c)))
}

/** An integer combination of joint angles: binary angles add modulo one turn, for free. */
final case class AngleSum(terms: Seq[(Int, Int)]) {
  require(terms.nonEmpty && terms.forall(_._2 != 0), s"AngleSum: empty or zero terms $terms")
  require(
    terms.map(_._1) == terms.map(_._1).sorted.distinct,
    s"AngleSum: joints must be sorted and distinct in $terms"
  )

  /** Input angles rounded into this sum (each adds its rounding error). */
  def weight: Int = terms.map(_._2.abs).sum
  def joints: Seq[Int] = terms.map(_._1)

  /** The sum in radians for joint angles `q` (rad). */
  def radians(q: Seq[Double]): Double = terms.map { case (j, k) => k * q(j) }.sum
  override def toString: String =
    terms.map { case (j, k) => (if (k == 1) "" else s"$k") + s"q${j + 1}" }.mkString("+")
}
object AngleSum {
  def of(joint: Int): AngleSum = AngleSum(Seq(joint -> 1))
  def of(joints: Int*): AngleSum = AngleSum(
    joints.groupBy(identity).toSeq.map { case (j, js) => j -> js.size }.sortBy(_._1)
  )
}

sealed abstract class TrigFn(val name: String) { override def toString: String = name }
object TrigFn {
  case object Sin extends TrigFn("sin")
  case object Cos extends TrigFn("cos")

  /** The function in double precision. */
  def reference(fn: TrigFn, rad: Double): Double = if (fn == Sin) math.sin(rad) else math.cos(rad)
}

/** One operation of the datapath. Constants are SI values, folded at elaboration. */
sealed trait Op { def operands: Seq[NodeId] }
object Op {
  final case class Const(value: Double) extends Op { def operands: Seq[NodeId] = Nil }
  final case class Input(signal: Signal) extends Op { def operands: Seq[NodeId] = Nil }
  final case class Trig(fn: TrigFn, angle: AngleSum) extends Op { def operands: Seq[NodeId] = Nil }
  final case class Add(a: NodeId, b: NodeId) extends Op { def operands: Seq[NodeId] = Seq(a, b) }
  final case class Sub(a: NodeId, b: NodeId) extends Op { def operands: Seq[NodeId] = Seq(a, b) }
  final case class Neg(a: NodeId) extends Op { def operands: Seq[NodeId] = Seq(a) }
  final case class Mul(a: NodeId, b: NodeId) extends Op { def operands: Seq[NodeId] = Seq(a, b) }
}

/** A named result of the graph (a joint torque). */
final case class Output(name: String, node: NodeId)

/**
 * A datapath as an expression graph: operations in topological order (operands first), every node reachable
 * from an output, common subexpressions shared. The single description of a datapath's structure; the
 * reference, the analyses, the bit-accurate model, the schedule and the hardware are interpretations of it.
 */
final case class Graph(ops: IndexedSeq[Op], outputs: IndexedSeq[Output]) {
  ops.zipWithIndex.foreach { case (op, i) =>
    require(op.operands.forall(_.index < i), s"Graph: node $i uses a later node")
  }
  require(outputs.forall(o => o.node.index >= 0 && o.node.index < ops.size), "Graph: an output names no node")

  def apply(id: NodeId): Op = ops(id.index)
  def ids: IndexedSeq[NodeId] = ops.indices.map(NodeId(_))

  /** How often each node is read: its occurrences as an operand, and as an output (read by the port). */
  lazy val readers: IndexedSeq[Int] = {
    val counts = Array.fill(ops.size)(0)
    ops.foreach(_.operands.foreach(x => counts(x.index) += 1))
    outputs.foreach(o => counts(o.node.index) += 1)
    counts.toIndexedSeq
  }

  /** Evaluate every node in order with `f`, given the values of its operands. */
  def fold[T](f: (Op, NodeId => T) => T): IndexedSeq[T] =
    ops.foldLeft(Vector.empty[T])((done, op) => done :+ f(op, id => done(id.index)))

  /** One node as a line of a report: `n7 = n3 * n5`, `n2 = sin(q2+q3)`, `n0 = 1.23`. */
  def describe(id: NodeId): String = s"n${id.index} = " + (apply(id) match {
    case Op.Const(v)    => v.toString
    case Op.Input(s)    => s.toString
    case Op.Trig(fn, a) => s"$fn($a)"
    case Op.Add(a, b)   => s"n${a.index} + n${b.index}"
    case Op.Sub(a, b)   => s"n${a.index} - n${b.index}"
    case Op.Neg(a)      => s"-n${a.index}"
    case Op.Mul(a, b)   => s"n${a.index} * n${b.index}"
  })

  def angles: Seq[AngleSum] = ops.collect { case Op.Trig(_, a) => a }.distinct
  def signals: Seq[Signal] = ops.collect { case Op.Input(s) => s }.distinct

  /** Operation counts after folding and sharing. */
  def counts: GraphCounts = {
    def isConst(id: NodeId) = apply(id).isInstanceOf[Op.Const]
    val muls = ops.collect { case m: Op.Mul => m }
    GraphCounts(
      multiplications = muls.size,
      constantMultiplications = muls.count(m => isConst(m.a) || isConst(m.b)),
      additions = ops.count { case _: Op.Add | _: Op.Sub => true; case _ => false },
      negations = ops.count(_.isInstanceOf[Op.Neg]),
      constants = ops.count(_.isInstanceOf[Op.Const]),
      sinCos = angles.size
    )
  }
}

final case class GraphCounts(
    multiplications: Int,
    constantMultiplications: Int,
    additions: Int,
    negations: Int,
    constants: Int,
    sinCos: Int
) {
  def variableMultiplications: Int = multiplications - constantMultiplications
}
