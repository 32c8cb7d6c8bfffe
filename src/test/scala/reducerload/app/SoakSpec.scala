package reducerload.app

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.compiler.{Compiled, Compiler}
import reducerload.sim.rtl.{Observed, VerilatorHarness}
import reducerload.testutil.{monitoredPlanar3, Seeds}

import scala.collection.mutable.ArrayBuffer

/**
 * The short form of `./sbt "run soak"` on designs SimulateEnginesSpec builds (same Verilog, same harness
 * cache entry): the monitored planar arm (host pulses and reads), planar3 at 7 clocks with one CORDIC unit
 * (each sample held valid until taken) and the default joint-3 preset; and the check shown to fail on a wrong
 * model and on corrupted observations.
 */
class SoakSpec extends AnyFlatSpec {
  behavior of "the soak"

  private def compiled(args: String*): Compiled =
    Compiler.compile(Cli.parse("simulate", args, Simulate.options, Simulate.flags).params, "test")

  private val monitored = monitoredPlanar3

  /** Soak `c` with `rates`; returns the result and everything observed. */
  private def soak(label: String, c: Compiled, rates: SoakRates, seed: Long): (Soak.Result, Seq[Observed]) = {
    assume(VerilatorHarness.available, "verilator is not installed")
    val plan = SoakPlan(c.arm, c.monitor, rates, Seeds(label, seed))
    val seen = ArrayBuffer.empty[Observed]
    val r = Soak.run(Soak.harness(c), plan, seen += _)
    Soak.report(r).foreach(l => println(s"[soak] $label: $l"))
    assert(r.mismatches == 0, r.examples.mkString("\n"))
    assert(r.taken == rates.samples && r.flagged > 0 && plan.resets > 0)
    (r, seen.toSeq)
  }

  private def mismatches(
      plan: SoakPlan,
      observed: Seq[Observed],
      expect: Int => reducerload.arm.ArmOutputCodes
  ) = {
    val check = new SoakCheck(plan, expect)
    observed.foreach(check.observe)
    check.finish()
    check.mismatches
  }

  it should "stream the monitored planar arm with bubbles, resets, out-of-range samples, snapshots, clears and reads, bit-exact" in {
    val rates = SoakRates(4000, resets = 8, snapshotOdds = 300, clearOdds = 700, readOdds = 10)
    val (r, observed) = soak("soak-monitored", compiled(monitored: _*), rates, 61L)
    val plan = r.plan
    assert(r.snapshots >= 5 && r.reads > 300 && plan.clears > 0)

    // The check can fail: a wrong model, and each kind of corrupted observation, is reported.
    val k = 1000
    assert(
      mismatches(
        plan,
        observed,
        i =>
          if (i == k) { val o = plan.expected(i); o.copy(tau = o.tau.updated(0, o.tau(0) + 1)) }
          else plan.expected(i)
      ) > 0,
      "a wrong torque went unnoticed"
    )
    def corrupted(what: String)(f: PartialFunction[Observed, Seq[Observed]]): Unit = {
      val at = observed.indexWhere(f.isDefinedAt, observed.size / 2)
      assert(at >= 0, s"no observation to corrupt for $what")
      val changed = observed.take(at) ++ f(observed(at)) ++ observed.drop(at + 1)
      assert(mismatches(plan, changed, plan.expected) > 0, s"$what went unnoticed")
    }
    corrupted("a dropped output") { case _: Observed.Output => Nil }
    corrupted("a duplicated output") { case o: Observed.Output => Seq(o, o.copy(cycle = o.cycle + 1)) }
    corrupted("a late output") { case o: Observed.Output => Seq(o.copy(cycle = o.cycle + 1)) }
    corrupted("a wrong read") { case Observed.ReadData(c, v) => Seq(Observed.ReadData(c, v ^ 1)) }
    corrupted("a missing read") { case _: Observed.ReadData => Nil }
    corrupted("a missing snapshotDone") { case _: Observed.SnapshotDone => Nil }
    corrupted("a late take") { case Observed.Taken(c) => Seq(Observed.Taken(c + 1)) }
  }

  it should "hold every sample valid until planar3 at 7 clocks with one CORDIC unit takes it, bit-exact" in {
    val c = compiled("--robot", "planar3", "--clocks-per-sample", "7", "--schedule.cordic-units", "1")
    val (r, observed) = soak("soak-planar3-7", c, SoakRates(3000, resets = 6), 62L)
    val takes = observed.collect { case Observed.Taken(t) => t }
    val held = takes.indices.count(k => takes(k) > r.plan.offerCycles(k))
    println(s"[soak] soak-planar3-7: $held of ${takes.size} samples held valid before they were taken")
    assert(held > takes.size / 2)
  }

  it should "stream the default joint-3 design (the old soak's), bit-exact" in {
    soak("soak-default", compiled(), SoakRates(3000, resets = 6), 63L)
  }
}
