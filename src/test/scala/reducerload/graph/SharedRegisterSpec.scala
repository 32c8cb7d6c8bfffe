package reducerload.graph

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.arm.ArmParams
import reducerload.compiler.Compiler
import reducerload.fixedpoint.Rounding
import reducerload.graph.Op.Mul
import reducerload.testutil.ArmGolden

/**
 * Registers products take turns in (`schedule.share-registers`): the allocation on cases known by hand, and
 * on the UR5's shared schedules every member found in its register in each cycle it is read, by replaying the
 * writes of every member over two samples (not by the residue sets the allocation works with).
 */
class SharedRegisterSpec extends AnyFlatSpec {
  behavior of "SharedRegister.allocate"

  private def c(id: Int, ready: Int, last: Int, unit: Int = 0, drop: Int = 5, width: Int = 20) =
    SharedRegister.Candidate(NodeId(id), unit, drop, Rounding.Truncate, width, ready, last)

  it should "put products whose cycles do not meet in one register, the widest width, and leave the rest alone" in {
    // interval 4: 1 holds residues 0-1, 2 holds 2-3 (wrapping: 6-7), 3 holds 1 (meets 1)
    val regs = SharedRegister.allocate(4, Seq(c(1, 0, 1), c(2, 6, 7, width = 24), c(3, 1, 1)))
    assert(regs == IndexedSeq(SharedRegister(0, IndexedSeq(NodeId(1), NodeId(2)), 24)))
  }

  it should "share only within one unit and one rounding" in {
    assert(SharedRegister.allocate(4, Seq(c(1, 0, 0), c(2, 1, 1, unit = 1))).isEmpty)
    assert(SharedRegister.allocate(4, Seq(c(1, 0, 0), c(2, 1, 1, drop = 6))).isEmpty)
    assert(
      SharedRegister
        .allocate(
          4,
          Seq(c(1, 0, 0), SharedRegister.Candidate(NodeId(2), 0, 5, Rounding.HalfUp, 20, 1, 1))
        )
        .isEmpty
    )
  }

  it should "fill a register on the whole circle: four products of one residue each at interval 4" in {
    val regs = SharedRegister.allocate(4, Seq(c(1, 4, 4), c(2, 1, 1), c(3, 10, 10), c(4, 3, 3)))
    assert(regs.map(_.members.map(_.index)) == IndexedSeq(IndexedSeq(1, 2, 3, 4)))
  }

  it should "refuse a product read after the interval (it needs a chain of its own)" in {
    val e = intercept[IllegalArgumentException](SharedRegister.allocate(4, Seq(c(1, 0, 4))))
    assert(e.getMessage.contains("not within the interval of 4"))
  }

  private lazy val ur5 = ArmGolden.of("ur5").head.config

  /** Every member of every shared register is the register's last write in each cycle it is read. */
  private def replayed(p: ArmParams): Int = {
    val s = p.schedule
    val ii = s.clocksPerSample
    assert(s.sharedRegisters.nonEmpty, s"no register shared at $ii clocks per sample")
    s.sharedRegisters.foreach { r =>
      val rules = r.members.map(p.analysis.productRounding).map(x => (x.drop, x.rounding)).distinct
      assert(rules.size == 1, s"$r: members round differently: $rules")
      assert(r.members.forall(m => s.slot(m).get.unit.contains(r.unit)), s"$r: a member on another unit")
      assert(r.width == r.members.map(p.analysis(_).format.width).max)
      // writes at the end of cycle ready - 1 of every sample in flight around sample k, which every read of
      // sample k must find as its own member's
      val k = s.latency / ii + 2
      val writes = for { n <- 0 to 2 * k; m <- r.members } yield (s(m).get - 1 + n * ii, m, n)
      r.members.foreach { m =>
        s.reads(m.index).foreach { read =>
          val at = read + k * ii
          val last = writes.filter(_._1 < at).maxBy(_._1)
          assert(
            last._2 == m && last._3 == k,
            s"$r: $m read in cycle $at finds ${last._2} of sample ${last._3}"
          )
        }
      }
    }
    s.sharedRegisters.map(_.members.size).sum
  }

  it should "hold every member in its register whenever it is read, on the UR5 direct and with registered routes" in {
    Seq(false, true).foreach { routed =>
      val p = Compiler.arm(
        ur5.copy(
          targetError = Seq(1e-3),
          schedule = ScheduleRequest(
            clocksPerSample = Some(17),
            maxMultipliers = Some(66),
            listOrder = Some(ListOrder.ByHeight),
            shareRegisters = true
          ),
          datapath = ur5.datapath.copy(reassociate = Reassociation.Sums, registeredRoutes = Some(routed))
        )
      )
      val shared = replayed(p)
      val unshared = p.copy(scheduleRequest = p.scheduleRequest.copy(shareRegisters = false))
      val products = p.graph.ids.count(id => p.graph(id).isInstanceOf[Mul])
      println(
        f"UR5 17 clocks, routed $routed: $shared of $products products in ${p.schedule.sharedRegisters.size} " +
          f"shared registers; held register bits ${unshared.heldRegisterBits} -> ${p.heldRegisterBits}"
      )
      assert(p.heldRegisterBits < unshared.heldRegisterBits)
    }
  }
}
