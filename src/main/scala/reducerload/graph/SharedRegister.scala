package reducerload.graph

import reducerload.fixedpoint.Rounding

/**
 * A register that products of one multiplier unit take turns in (`schedule.share-registers`, registers
 * storage at 2 clocks per sample or more). Each member is written at the end of the cycle before it is ready
 * and read within the interval; no two members' cycles from ready to last read meet modulo the interval, so
 * each member is in the register in every cycle it is read, for every sample. The members drop the same bits
 * with the same rounding, so the register takes the unit's output rounded once, at the widest member's width;
 * a reader takes its member's width of it, the bits that member's own register would have held.
 *
 * @param members
 *   the products, the first the one whose write comes first in the interval
 */
final case class SharedRegister(unit: Int, members: IndexedSeq[NodeId], width: Int) {
  require(members.size >= 2, s"SharedRegister: a register of one member (${members.mkString}) is not shared")
}

object SharedRegister {

  /**
   * A product that may share a register: its unit, the bits it drops and how, its width, the cycle from which
   * it is in its register and the last cycle it is read (within the interval).
   */
  final case class Candidate(
      id: NodeId,
      unit: Int,
      drop: Int,
      rounding: Rounding,
      width: Int,
      ready: Int,
      lastRead: Int
  ) {
    require(lastRead >= ready, s"SharedRegister: $id is read in $lastRead, before it is ready in $ready")

    /** The residues it holds the register in at `interval` clocks per sample. */
    def residues(interval: Int): Set[Int] = (ready to lastRead).map(_ % interval).toSet
  }

  /**
   * The shared registers of `candidates` at `interval` clocks per sample: per unit and rounding, the longest
   * lived first, each into the first register it fits beside (first fit on the circle of residues, a few
   * registers above the fewest at worst; the fewest is NP-hard in general). Candidates left alone keep a
   * register of their own and are not listed.
   */
  def allocate(interval: Int, candidates: Seq[Candidate]): IndexedSeq[SharedRegister] = {
    candidates.foreach(c =>
      require(
        c.lastRead - c.ready < interval,
        s"SharedRegister: ${c.id} is read ${c.lastRead - c.ready} cycles after it is ready, not within the " +
          s"interval of $interval"
      )
    )
    candidates
      .groupBy(c => (c.unit, c.drop, c.rounding))
      .toIndexedSeq
      .sortBy { case ((unit, drop, rounding), _) => (unit, drop, rounding.name) }
      .flatMap { case ((unit, _, _), group) =>
        val filled = group
          .sortBy(c => (-(c.lastRead - c.ready), c.id.index))
          .foldLeft(Vector.empty[(Set[Int], Vector[Candidate])]) { case (registers, c) =>
            val held = c.residues(interval)
            registers.indexWhere(r => (r._1 & held).isEmpty) match {
              case -1 => registers :+ (held -> Vector(c))
              case k  => registers.updated(k, (registers(k)._1 ++ held, registers(k)._2 :+ c))
            }
          }
        filled.collect {
          case (_, members) if members.size >= 2 =>
            SharedRegister(unit, members.sortBy(_.ready % interval).map(_.id), members.map(_.width).max)
        }
      }
  }
}
