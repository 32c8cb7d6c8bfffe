package reducerload.graph

/**
 * A block RAM a multiplier unit writes its product into every clock (`schedule.product-memories`, registers
 * storage at 2 clocks per sample or more), at the residue of the cycle, so that products read three clocks or
 * more after they are ready need no capture register of their own: a shared unit moves on to its next
 * multiply the clock after, and each product waiting for its reader otherwise takes a register (a third of
 * the UR5 latency recipe's logic elements: docs/timing-closure.md, "which registers take an LE of their
 * own"). One read port: each cycle of the interval reads at most one member, through the memory's output
 * register into a register in logic, which the reader takes in that cycle.
 *
 * A member is in the unit's product register in the cycle before it is ready, so it is written in the slot of
 * that residue; a read in cycle `c` gives the slot's word in the register after the memory's in `c` (the
 * address [[ProductMemory.readDelay]] clocks earlier). Reads lie in `ready + readDelay .. ready + interval`:
 * the slot is written before its first read and not again, by the next sample, before its last; no read meets
 * a write of its own slot. The word is the product's bits `low` until `high` (exclusive): each member
 * truncates the product (a slice, so a reader's slice of the word is the bits its own register would hold).
 *
 * @param members
 *   the products stored, with the cycles each is read in
 */
final case class ProductMemory(unit: Int, members: IndexedSeq[ProductMemory.Candidate], low: Int, high: Int) {
  require(members.nonEmpty, s"ProductMemory: unit $unit's memory has no member")
  require(
    low >= 0 && high - low >= 1 && high - low <= ProductMemory.maxWordBits,
    s"ProductMemory: unit $unit's word of bits $low until $high is not 1 to ${ProductMemory.maxWordBits} bits"
  )

  /** Bits of a word. */
  def width: Int = high - low
}

object ProductMemory {

  /** The block RAM's own registers on a read: its address register and its output register (an M9K's). */
  val blockRamRegisters: Int = 2

  /**
   * Registers in logic after the block RAM's output register (a word's bits in logic elements each), which
   * the placer puts toward the readers. The word straight from the block RAM's output register crossed the
   * die to its readers in one clock: the UR5 latency recipe routed at 124.0 / 134.6 MHz on seeds 1 / 2, with
   * one register 151.9 on seed 2 (docs/timing-closure.md, "products read from block RAM").
   */
  val fabricRegisters: Int = 1

  /** Clocks from a read's address to its word at the readers. */
  val readDelay: Int = blockRamRegisters + fabricRegisters

  /**
   * Whether a product ready in cycle `ready` can be read from its memory in cycle `read` at `interval` clocks
   * per sample: its slot is written before the read's address and not again, by the next sample, before it.
   */
  def inWindow(ready: Int, read: Int, interval: Int): Boolean =
    read >= ready + readDelay && read <= ready + interval

  /**
   * Widest word: an M9K's (256 x 36), so that each memory is one block at any interval up to 256 clocks.
   */
  val maxWordBits: Int = 36

  /**
   * A truncated product that may be stored: its unit, the product's bits it keeps (`drop` until `drop +
   * width`, of the unit's `productBits`), the cycle from which its own register would hold it and the cycles
   * it is read in.
   */
  final case class Candidate(
      id: NodeId,
      unit: Int,
      drop: Int,
      width: Int,
      productBits: Int,
      ready: Int,
      reads: Seq[Int]
  ) {
    require(reads.nonEmpty, s"ProductMemory: $id is never read")
    require(ready >= 1 && drop >= 0, s"ProductMemory: $id is ready in $ready, drops $drop bits")

    /** Highest product bit its value depends on, plus one (a wider value repeats the product's sign). */
    def top: Int = (drop + width).min(productBits)

    /**
     * The slot it is written in at `interval` clocks per sample: the residue of the cycle before it is ready,
     * when the unit's product register holds it.
     */
    def slot(interval: Int): Int = (ready - 1) % interval

    /** Whether every read lies where a memory can serve it at `interval` clocks per sample. */
    def storable(interval: Int): Boolean = reads.forall(inWindow(ready, _, interval))
  }

  /**
   * The memories of `candidates` at `interval` clocks per sample: per unit, the widest product first (then by
   * node), each taken when its reads' residues are free on the read port and the word stays within
   * [[maxWordBits]]. A unit with fewer than two members gets none (a block RAM for one register). Candidates
   * left out keep a register of their own.
   */
  def allocate(interval: Int, candidates: Seq[Candidate]): IndexedSeq[ProductMemory] =
    candidates
      .filter(_.storable(interval))
      .groupBy(_.unit)
      .toIndexedSeq
      .sortBy(_._1)
      .flatMap { case (unit, group) =>
        val taken = group
          .sortBy(c => (-c.width, c.id.index))
          .foldLeft(Vector.empty[Candidate]) { (taken, c) =>
            val used = taken.flatMap(_.reads.map(_ % interval)).toSet
            val residues = c.reads.map(_ % interval)
            val members = taken :+ c
            val span = members.map(_.top).max - members.map(_.drop).min
            if (residues.distinct.size == residues.size && !residues.exists(used) && span <= maxWordBits)
              members
            else taken
          }
        Option.when(taken.size >= 2)(
          ProductMemory(unit, taken.sortBy(_.ready % interval), taken.map(_.drop).min, taken.map(_.top).max)
        )
      }
}
