package reducerload.graph

/**
 * A block RAM a CORDIC unit writes its sine (or cosine) into every clock (`schedule.sin-cos-memories`,
 * registers storage at 2 clocks per sample or more), at a pointer that counts clocks modulo
 * [[SinCosMemory.depth]], so that a sin or cos read [[ProductMemory.readDelay]] clocks or more after it is
 * ready, up to about a block's depth of clocks later, needs no register of its own: on the UR5's latency
 * recipe each of the 16 sin/cos values is held for two intervals or more, in a chain of registers and then a
 * block-RAM delay with its register in logic (docs/timing-closure.md, "sin and cos read from block RAM").
 *
 * One read port: each residue of the interval reads at most one value, addressed [[ProductMemory.readDelay]]
 * clocks before the read (the pointer minus how far back the value was written), through the block RAM's
 * output register into a register in logic, which every reader of that cycle takes. A value's reads may lie
 * in several memories of its function (each written alike): a unit port whose reads share one memory takes
 * them as one multiplexer input.
 *
 * @param reads
 *   the reads it serves, one per residue
 */
final case class SinCosMemory(unit: Int, fn: TrigFn, reads: IndexedSeq[SinCosMemory.Read]) {
  require(reads.nonEmpty, s"SinCosMemory: unit $unit's $fn memory serves no read")
}

object SinCosMemory {

  /**
   * Words of a memory and the pointer's modulus: an M9K's depth at 36 bits (256 x 36), so each memory is one
   * block, and a power of two, so the pointer wraps by itself.
   */
  val depth: Int = 256

  /**
   * A read of value `value`, in its register from cycle `ready` (written into the memory in `ready - 1`), in
   * cycle `cycle`, on the unit of function `fn`.
   */
  final case class Read(unit: Int, fn: TrigFn, value: NodeId, ready: Int, cycle: Int) {
    require(
      inWindow(ready, cycle),
      s"SinCosMemory: $value ready in $ready cannot be read from memory in $cycle"
    )

    /** Clocks from the write (`ready - 1`) to the read's address (`cycle - readDelay`). */
    def back: Int = backOf(ready, cycle)
  }

  /**
   * Whether a value ready in cycle `ready` can be read from memory in cycle `read`: after the block RAM's and
   * the logic's registers, and before the pointer comes round to its word again.
   */
  def inWindow(ready: Int, read: Int): Boolean = backOf(ready, read) >= 1 && backOf(ready, read) < depth

  /** Clocks from the write of a value ready in `ready` to the address of its read in `read`. */
  private def backOf(ready: Int, read: Int): Int = read - ProductMemory.readDelay - (ready - 1)

  /**
   * The memories serving `reads` at `interval` clocks per sample, per unit and function: each read in the
   * first memory whose residue is free, the reads of one multiplier port (`portOf`; none for other readers)
   * together where the residues allow (the port then has one multiplexer input for them), ports with the most
   * reads first; a new memory where none is free.
   */
  def allocate(interval: Int, reads: Seq[Read], portOf: Read => Seq[MulPort]): IndexedSeq[SinCosMemory] =
    reads
      .groupBy(r => (r.unit, r.fn))
      .toIndexedSeq
      .sortBy { case ((unit, fn), _) => (unit, fn.name) }
      .flatMap { case ((unit, fn), group) =>
        val byPort = group.flatMap(r => portOf(r).map(_ -> r)).groupMap(_._1)(_._2)
        val order =
          byPort.toSeq.sortBy { case (port, rs) => (-rs.size, port.unit, port.port) }.map(_._2) :+ group
        val memories = order.foldLeft(Vector.empty[Map[Int, Read]]) { (memories, portReads) =>
          portReads.foldLeft(memories) { (ms, r) =>
            if (ms.exists(_.get(r.cycle % interval).contains(r))) ms
            else {
              // the memories this port's reads are in already, most first, then the others in order
              val mine = portReads.flatMap(o =>
                ms.indexWhere(_.get(o.cycle % interval).contains(o)) match {
                  case -1 => None
                  case k  => Some(k)
                }
              )
              val preferred = mine.groupBy(identity).toSeq.sortBy(k => (-k._2.size, k._1)).map(_._1)
              (preferred ++ ms.indices).find(k => !ms(k).contains(r.cycle % interval)) match {
                case Some(k) => ms.updated(k, ms(k) + (r.cycle % interval -> r))
                case None    => ms :+ Map(r.cycle % interval -> r)
              }
            }
          }
        }
        memories.map(m => SinCosMemory(unit, fn, m.toIndexedSeq.sortBy(_._1).map(_._2)))
      }

  /** Port `port` (0 the wide, 1 the narrow) of multiplier unit `unit`. */
  final case class MulPort(unit: Int, port: Int)
}
