package reducerload.graph

import org.scalatest.flatspec.AnyFlatSpec

/**
 * Block RAMs the CORDIC units write sin and cos into (`schedule.sin-cos-memories`): the allocation on cases
 * known by hand, and on the UR5's latency recipe each read finding its value's word, by replaying every
 * clock's write over several samples (not by the rules the allocation works with).
 */
class SinCosMemorySpec extends AnyFlatSpec {
  behavior of "SinCosMemory.allocate"

  private def r(value: Int, ready: Int, cycle: Int, fn: TrigFn = TrigFn.Sin, unit: Int = 0) =
    SinCosMemory.Read(unit, fn, NodeId(value), ready, cycle)

  it should "serve one read per residue and memory, a new memory where every one has the residue taken" in {
    // interval 4: reads in residues 1, 1, 2
    val reads = Seq(r(1, 2, 5), r(2, 3, 9), r(2, 3, 6))
    val memories = SinCosMemory.allocate(4, reads, _ => Nil)
    assert(memories.size == 2)
    memories.foreach(m => assert(m.reads.map(_.cycle % 4).distinct.size == m.reads.size))
    assert(memories.flatMap(_.reads).toSet == reads.toSet)
  }

  it should "keep sines and cosines, and units, apart" in {
    val memories =
      SinCosMemory.allocate(4, Seq(r(1, 2, 5), r(2, 2, 6, TrigFn.Cos), r(3, 2, 7, unit = 1)), _ => Nil)
    assert(
      memories.map(m => (m.unit, m.fn.name, m.reads.size)).toSet == Set(
        (0, "sin", 1),
        (0, "cos", 1),
        (1, "sin", 1)
      )
    )
  }

  it should "put a multiplier port's reads in one memory where their residues allow" in {
    // interval 4: port A reads 1 in residue 1 and 3 in residue 2; port B reads 2 in residue 2. Taken in
    // order 1, 2 would share a memory and 3 go to a second, so that A needed two inputs.
    val a = SinCosMemory.MulPort(0, 0)
    val b = SinCosMemory.MulPort(1, 0)
    val reads = Seq(r(1, 2, 5), r(2, 2, 6), r(3, 3, 10))
    val ports = Map(reads(0) -> Seq(a), reads(1) -> Seq(b), reads(2) -> Seq(a))
    val memories = SinCosMemory.allocate(4, reads, ports)
    val ofA = memories.filter(_.reads.exists(x => ports(x).contains(a)))
    assert(ofA.size == 1, s"port A reads ${ofA.size} memories")
  }

  it should "refuse a read before the block RAM's registers have the word, or after the pointer came round" in {
    assert(SinCosMemory.inWindow(5, 5 + ProductMemory.readDelay))
    assert(!SinCosMemory.inWindow(5, 4 + ProductMemory.readDelay))
    assert(!SinCosMemory.inWindow(5, 4 + ProductMemory.readDelay + SinCosMemory.depth))
    val e = intercept[IllegalArgumentException](r(1, 5, 6))
    assert(e.getMessage.contains("cannot be read from memory"))
  }

  it should "find every read's value in its word, on the UR5's latency recipe" in {
    val p = Ur5LatencyRecipe(ScheduleRequest(sinCosMemories = true))
    val s = p.schedule
    val ii = s.clocksPerSample
    val depth = SinCosMemory.depth
    assert(s.sinCosMemories.nonEmpty, "no sin/cos memory")
    s.sinCosMemories.foreach { m =>
      val residues = m.reads.map(_.cycle % ii)
      assert(residues.distinct.size == residues.size, s"$m: two reads in one residue")
      assert(
        m.reads.forall(x => p.graph(x.value) match { case Op.Trig(fn, _) => fn == m.fn; case _ => false }),
        s"$m: a read of another function"
      )
      // Sample n enters in cycle n * II; the CORDIC unit's output holds value x of sample n in cycle
      // n * II + ready(x) - 1, and every clock writes the output at the pointer (the clock modulo the depth). A
      // read in cycle c addresses the pointer of its address cycle minus `back`: the word written then must be
      // its value's, of its sample, and the writer of cycle t is found from the schedule alone.
      val values = m.reads.map(_.value).distinct
      def writer(t: Int): Option[(NodeId, Int)] = values.collectFirst {
        case x if Math.floorMod(t - (s(x).get - 1), ii) == 0 => (x, Math.floorDiv(t - (s(x).get - 1), ii))
      }
      val n = s.latency / ii + 20 // a sample whose reads cross the pointer's wrap
      m.reads.foreach { read =>
        val addressed = n * ii + read.cycle - ProductMemory.readDelay
        val pointer = Math.floorMod(addressed, depth)
        val word = Math.floorMod(pointer - read.back, depth)
        // the last clock before the address cycle that wrote that word
        val written =
          (addressed - 1 to addressed - depth by -1).find(t => Math.floorMod(t, depth) == word).get
        assert(
          writer(written).contains((read.value, n)),
          s"$m: ${read.value} read in cycle ${read.cycle} of sample $n finds ${writer(written)}"
        )
      }
    }
    // every sin/cos read in a window is served, and a value read only from memories has no register
    val trig = p.graph.ids.filter(p.graph(_).isInstanceOf[Op.Trig])
    trig.foreach { x =>
      val inWindow = s.reads(x.index).filter(SinCosMemory.inWindow(s(x).get, _))
      assert(inWindow.forall(c => s.sinCosMemoryOf.contains((x, c))), s"$x: a read in a window left out")
      assert(s.ownReads(x) == s.reads(x.index).filterNot(inWindow.contains))
    }
    val off = p.copy(scheduleRequest = p.scheduleRequest.copy(sinCosMemories = false))
    // the sin/cos values' own registers (first registers and chains) and block-RAM delays, without and with
    def held(q: reducerload.arm.ArmParams) = trig.flatMap(q.heldTaps).map(t => (t.registers, t.delayed.size))
    val (registersOff, delaysOff) = (held(off).map(_._1).sum, held(off).map(_._2).sum)
    val (registersOn, delaysOn) = (held(p).map(_._1).sum, held(p).map(_._2).sum)
    println(
      s"UR5 18 clocks: ${s.sinCosMemoryOf.size} sin/cos reads from ${s.sinCosMemories.size} memories; the " +
        s"values' registers $registersOff -> $registersOn, their block-RAM delays $delaysOff -> $delaysOn"
    )
    // a memory and its word register take the place of several delays, each with its register in logic
    assert(registersOn < registersOff && delaysOn + s.sinCosMemories.size < delaysOff)
    assert(p.latency == off.latency, "sin/cos memories changed the latency")
  }
}
