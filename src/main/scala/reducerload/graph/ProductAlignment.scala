package reducerload.graph

/**
 * A multiply of memory storage with its product aligned: each port's operand shifted left by `shifts(port)`
 * bits, `fromTable(port)` of them in the table's copy of a constant operand and the rest by its port's shift
 * multiplexer, and the product rounded by `drop` bits, the analysis's drop plus the shifts.
 */
final case class AlignedProduct(shifts: IndexedSeq[Int], fromTable: IndexedSeq[Int], drop: Int) {

  /** The bits each port's shift multiplexer shifts by (the rest of the port's shift is in the table). */
  def muxShifts: IndexedSeq[Int] = shifts.zip(fromTable).map { case (s, t) => s - t }
}

/**
 * Where memory storage rounds each product. A multiply's node keeps `drop` fewer fraction bits than the full
 * product of its operands' formats, and the products of one unit drop many different counts (the per-node
 * formats); a rounding per count ahead of the bank's write register, with the multiplexer among them, sat on
 * the route from the unit to its block RAM and limited the clock of those designs (docs/timing-closure.md).
 * An operand shifted left by s bits within its port's width makes the product 2^s times larger, and dropping
 * s more bits then gives the same value exactly, for either rounding. So each product is raised to one of a
 * few drops per unit, as many as cost the least logic: each drop is a rounding, each shift a port's
 * multiplexer takes is an input of it (counts before and after: docs/timing-closure.md).
 *
 * The shift of a constant operand is in the table (free); a stored operand is shifted after its operand
 * register, by a multiplexer among the port's few shifts, in the cycle of the issue. A port keeps the shifts
 * it already has where a product allows.
 */
final class ProductAlignment(b: BankedSchedule) {
  private val analysis = b.base.analysis

  /** Each multiplier unit's multiplies, in the schedule's order. */
  private val onUnit: IndexedSeq[IndexedSeq[PlacedOp]] =
    (0 until b.base.multiplierUnits).map(b.opsOn(UnitKind.Multiplier, _))

  /** Each multiplier unit's port widths. */
  private val widthsOn: IndexedSeq[IndexedSeq[Int]] = onUnit.indices.map(b.base.unitShape(_).widths)

  /** Bits port `port` of `o`'s unit leaves above `o`'s operand there (a constant's table copy: none). */
  private def spare(o: PlacedOp, port: Int): Int =
    o.operands(port).carried.fold(0)(x => widthsOn(o.unit)(port) - analysis(x).format.width)

  /** The most bits `o`'s product can be raised by: its operands' spare bits. */
  private def room(o: PlacedOp): Int = spare(o, 0) + spare(o, 1)

  private def isConstant(o: PlacedOp, port: Int) = o.operands(port).isInstanceOf[Operand.Constant]

  /**
   * Unit `u`'s plan with each product shifted by at most `cap` bits: the fewest drops such that every product
   * reaches one (intervals [low, high], greedy by the right end), each then lowered to the highest low of the
   * products that take it (fewer shifted bits). A cap of 0 rounds each product where the analysis does.
   */
  private def plan(u: Int, cap: Int): ProductAlignment.UnitPlan = {
    val widths = widthsOn(u)
    val ops = onUnit(u)
    def low(o: PlacedOp) = analysis.productRounding(o.node).drop
    def high(o: PlacedOp) = low(o) + math.min(cap, room(o))
    val chosen = ops.sortBy(o => (high(o), low(o))).foldLeft(Vector.empty[Int]) { (ds, o) =>
      if (ds.exists(d => d >= low(o) && d <= high(o))) ds else ds :+ high(o)
    }
    def nearest(ds: Seq[Int], o: PlacedOp) = ds.filter(d => d >= low(o) && d <= high(o)).min
    val drops = chosen.map(d => ops.filter(nearest(chosen, _) == d).map(low).max).distinct.sorted
    val used = Array.fill(2)(Set.empty[Int])
    // Products of two stored operands first: they set the ports' shifts, which a constant's product can share.
    val aligned = ops.sortBy(o => (0 to 1).exists(isConstant(o, _))).map { o =>
      var rest = nearest(drops, o) - low(o)
      val shifts = Array(0, 0)
      val fromTable = Array(0, 0)
      // A constant takes its shift in the table, keeping a shift its port's multiplexer already has.
      (0 to 1).filter(isConstant(o, _)).foreach { port =>
        val mux = used(port).filter(_ <= math.min(rest, spare(o, port))).maxOption.getOrElse(0)
        val table = math.min(rest - mux, spare(o, port) - mux)
        shifts(port) = mux + table
        fromTable(port) = table
        rest -= mux + table
      }
      // The rest on one stored operand with the spare bits: one whose port already shifts by that, else the
      // narrower port (its multiplexer is narrower); both if neither has enough.
      val alone = (0 to 1).filter(p => !isConstant(o, p) && spare(o, p) - shifts(p) >= rest)
      if (rest > 0 && alone.nonEmpty) {
        val p = alone.minBy(p => (!used(p).contains(shifts(p) + rest), widths(p)))
        shifts(p) += rest
        rest = 0
      }
      (0 to 1).foreach { p =>
        val s = math.min(rest, spare(o, p) - shifts(p))
        shifts(p) += s
        rest -= s
      }
      require(rest == 0, s"ProductAlignment: a product of unit $u cannot reach its drop")
      (0 to 1).foreach(p => used(p) += shifts(p) - fromTable(p))
      o.node -> AlignedProduct(shifts.toIndexedSeq, fromTable.toIndexedSeq, low(o) + shifts.sum)
    }
    ProductAlignment.UnitPlan(drops, aligned.toMap)
  }

  /**
   * A plan's logic: a rounding of the unit's result width per drop, and each port's shift multiplexer (none
   * for one shift), an input of the port's width per shift.
   */
  private def cost(u: Int, plan: ProductAlignment.UnitPlan): Double = {
    val muxInputs = (0 to 1).map { port =>
      ProductAlignment.muxInputs(onUnit(u).map(o => plan.products(o.node).muxShifts(port)).distinct.size) *
        widthsOn(u)(port)
    }.sum
    LogicCost.roundingBit * plan.drops.size * b.unitWidth(
      Bank.Products(u)
    ) + LogicCost.shiftMuxBit * muxInputs
  }

  /**
   * Each unit's cheapest plan over the caps, from none (the analysis's roundings) to the operands' spare bits
   * (the fewest drops), among those of at most [[ProductAlignment.maxDrops]] drops: a unit with few distinct
   * drops keeps them rather than pay for wide shift multiplexers.
   */
  private val plans: IndexedSeq[ProductAlignment.UnitPlan] = onUnit.indices.map { u =>
    val all = (0 to onUnit(u).map(room).maxOption.getOrElse(0)).map(plan(u, _))
    val few = all.filter(_.drops.size <= ProductAlignment.maxDrops)
    if (few.isEmpty) all.last else few.minBy(cost(u, _))
  }

  /** Each multiplier unit's drops, ascending: one rounding each ahead of the bank's write register. */
  def drops(unit: Int): IndexedSeq[Int] = plans(unit).drops

  /** A multiply's alignment. */
  def apply(o: PlacedOp): AlignedProduct = plans(o.unit).products(o.node)

  /** The shifts of a unit port's multiplexer, ascending (one: a fixed shift, no multiplexer). */
  def muxShifts(unit: Int, port: Int): IndexedSeq[Int] =
    onUnit(unit).map(o => apply(o).muxShifts(port)).distinct.sorted.toIndexedSeq.padTo(1, 0)
}

object ProductAlignment {

  /**
   * Drops a unit may round by: a 4-input multiplexer is one level of logic (ECP5: two LUTs and the slice's
   * multiplexer), and its select's route from the table's register then fits the clock; five or more drops
   * (the Z1 at 88 clocks, seed 2) put a level more on that route and limited the design.
   */
  val maxDrops: Int = 4

  /** Inputs of a shift multiplexer among `shifts` shifts: none for one (a fixed shift is wiring). */
  def muxInputs(shifts: Int): Int = if (shifts > 1) shifts else 0

  /** One unit's drops, ascending, and its multiplies' alignments. */
  private final case class UnitPlan(drops: IndexedSeq[Int], products: Map[NodeId, AlignedProduct])
}
