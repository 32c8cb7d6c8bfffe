package reducerload.graph

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.fixedpoint.Rounding

/**
 * Block RAMs units write their products into (`schedule.product-memories`): the allocation on cases known by
 * hand, and on the UR5's latency recipe each member found in its slot whenever it is read, by replaying every
 * clock's write over several samples (not by the residue rules the allocation works with).
 */
class ProductMemorySpec extends AnyFlatSpec {
  behavior of "ProductMemory.allocate"

  private def c(id: Int, ready: Int, reads: Seq[Int], unit: Int = 0, drop: Int = 5, width: Int = 20) =
    ProductMemory.Candidate(NodeId(id), unit, drop, width, 40, ready, reads)

  it should "take products read three clocks or more after they are ready, within the interval, one per " +
    "read residue, the widest first" in {
      // interval 6: 1 is read in residue 5, 2 in residues 3 and 4 (cycles 9, 10), 3 in residue 4 (meets 2,
      // narrower)
      val memories =
        ProductMemory.allocate(6, Seq(c(1, 1, Seq(5)), c(2, 6, Seq(9, 10), width = 24), c(3, 7, Seq(10))))
      // members in the order of their slots: 2 written in residue 5 (ready in 0), 1 in residue 0
      assert(memories.map(_.members.map(_.id.index)) == IndexedSeq(IndexedSeq(2, 1)))
      assert(memories.head.low == 5 && memories.head.high == 29)
    }

  it should "leave out a read before readDelay or after the interval, and a unit with one member" in {
    assert(ProductMemory.allocate(4, Seq(c(1, 1, Seq(3)), c(2, 2, Seq(5)))).isEmpty)
    assert(ProductMemory.allocate(4, Seq(c(1, 1, Seq(6)), c(2, 2, Seq(5)))).isEmpty)
    assert(ProductMemory.allocate(4, Seq(c(1, 1, Seq(4)), c(2, 2, Seq(5), unit = 1))).isEmpty)
  }

  it should "keep a word within an M9K's 36 bits, from the lowest bit kept to the highest the product has" in {
    // 2 keeps bits 20-37 of a 40-bit product: with 1 (bits 0-19) the word would be 38 bits
    val memories = ProductMemory.allocate(
      4,
      Seq(c(1, 1, Seq(4), drop = 0), c(2, 2, Seq(5), drop = 20, width = 18), c(3, 3, Seq(6), drop = 2))
    )
    assert(memories.map(_.members.map(_.id.index)) == IndexedSeq(IndexedSeq(1, 3)))
    assert(memories.head.high == 22)
    val top =
      ProductMemory.allocate(4, Seq(c(1, 1, Seq(4), drop = 16, width = 30), c(2, 2, Seq(5), drop = 17)))
    assert(top.head.high == 40 && top.head.width == 24, "bits above the product's repeat its sign")
  }

  it should "refuse a memory without members and a word wider than a block's" in {
    assert(
      intercept[IllegalArgumentException](ProductMemory(0, IndexedSeq.empty, 0, 1)).getMessage
        .contains("no member")
    )
    val e = intercept[IllegalArgumentException](ProductMemory(0, IndexedSeq(c(1, 1, Seq(4))), 0, 37))
    assert(e.getMessage.contains("1 to 36 bits"))
  }

  it should "find every member in its slot whenever it is read, on the UR5's latency recipe" in {
    val p = Ur5LatencyRecipe(ScheduleRequest(productMemories = true))
    val s = p.schedule
    val ii = s.clocksPerSample
    assert(s.productMemories.nonEmpty, "no product memory")
    s.productMemories.foreach { m =>
      val ids = m.members.map(_.id)
      assert(ids.forall(x => s.slot(x).get.unit.contains(m.unit)), s"$m: a member on another unit")
      assert(ids.forall(x => p.analysis.productRounding(x).rounding == Rounding.Truncate))
      // sample n enters in cycle n * II; the unit's product register holds member x of sample n in cycle
      // n * II + ready(x) - 1, and every clock writes the register into slot (cycle mod II); a read in cycle c
      // addresses its member's slot in c - readDelay
      val k = s.latency / ii + 2
      def writer(t: Int): Option[(NodeId, Int)] = ids.collectFirst {
        case x if Math.floorMod(t - (s(x).get - 1), ii) == 0 => (x, (t - (s(x).get - 1)) / ii)
      }
      val addressed = m.members.flatMap(o => o.reads.map(r => (r - ProductMemory.readDelay) % ii))
      assert(addressed.distinct.size == addressed.size, s"$m: two reads address it in one residue")
      m.members.foreach { member =>
        member.reads.foreach { read =>
          val issued = read + k * ii - ProductMemory.readDelay
          val slot = (s(member.id).get - 1) % ii
          // the last cycle before `issued` that wrote this slot, and none in `issued` itself
          assert(Math.floorMod(issued, ii) != slot, s"$m: ${member.id}'s read meets a write of its slot")
          val written = (issued - 1 to issued - ii by -1).find(t => Math.floorMod(t, ii) == slot).get
          assert(
            writer(written).contains((member.id, k)),
            s"$m: ${member.id} read in cycle ${read + k * ii} finds ${writer(written)}"
          )
        }
      }
    }
    val off = p.copy(scheduleRequest = p.scheduleRequest.copy(productMemories = false))
    println(
      s"UR5 18 clocks: ${s.productMemoryOf.size} products in ${s.productMemories.size} product memories; held " +
        s"register bits ${off.heldRegisterBits} -> ${p.heldRegisterBits}"
    )
    assert(p.heldRegisterBits < off.heldRegisterBits)
    assert(p.latency == off.latency, "product memories changed the latency")
    // the refinement moves reads into the memories' windows, apart on their ports: more than half the products
    // on units are members (a third, 91 of 260 on the README's recipe, before it did)
    val onUnits =
      p.graph.ids.count(x => p.graph(x).isInstanceOf[Op.Mul] && s.slot(x).exists(_.unit.isDefined))
    assert(
      s.productMemoryOf.size * 2 > onUnits,
      s"${s.productMemoryOf.size} of $onUnits products in memories"
    )

    // With shared registers too the memories choose first (a member needs no register at all) and the shared
    // registers take from the products left.
    val both = p.copy(scheduleRequest = p.scheduleRequest.copy(shareRegisters = true))
    val sharedOnly = both.copy(scheduleRequest = both.scheduleRequest.copy(productMemories = false))
    val b = both.schedule
    assert(b.productMemories == s.productMemories, "shared registers changed the product memories")
    assert(b.sharedRegisters.nonEmpty, "no shared register beside the memories")
    assert(b.sharedRegisters.flatMap(_.members).forall(!b.productMemoryOf.contains(_)), "a product in both")
    println(
      s"UR5 18 clocks with shared registers: ${b.productMemoryOf.size} products in memories, " +
        s"${b.sharedRegisterOf.size} in ${b.sharedRegisters.size} shared registers; held register bits " +
        s"${sharedOnly.heldRegisterBits} (shared alone) -> ${both.heldRegisterBits}"
    )
    assert(both.heldRegisterBits < sharedOnly.heldRegisterBits)
  }
}
