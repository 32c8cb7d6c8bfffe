package reducerload.arm

import circt.stage.ChiselStage
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.api.ReducerLoad
import reducerload.testutil.{EnableOrder, PayloadDesigns}

/**
 * No register loads under a `when` on a register declared after it ([[EnableOrder]]: firtool 1.62 then gives
 * some registers another register's enable, differently from run to run). Elaboration only, no simulation:
 * the designs whose hardware has such enables (accumulators, registered routes, readers' copies, block-RAM
 * storage, the bus wrappers, the payload, the monitor).
 */
class EnableOrderSpec extends AnyFlatSpec {
  behavior of "The emitted designs"

  private def check(args: String*): Unit = {
    val core = ReducerLoad.fromArgs(args: _*)
    val found = EnableOrder.violations(ChiselStage.emitCHIRRTL(core.top.generator()))
    if (found.nonEmpty) fail(s"${args.mkString(" ")}: ${found.take(5).mkString("; ")} (${found.size} in all)")
  }

  "EnableOrder" should "find a register loaded under a later register's value, and only that" in {
    val chirrtl =
      """circuit Top :
        |  module A :
        |    input clock : Clock
        |    reg early : UInt<8>, clock
        |    reg en : UInt<1>, clock
        |    reg late : UInt<8>, clock
        |    when en :
        |      connect late, early
        |    else :
        |      connect early.x, late
        |    connect early, late
        |  module B :
        |    input clock : Clock
        |    input c : UInt<1>
        |    reg en : UInt<1>, clock
        |    reg r : UInt<8>, clock
        |    when c :
        |      connect r, en
        |    when en :
        |      connect r, r
        |""".stripMargin
    // in A: `early` under `en` (in the else too), not `late`, nor `early` after the `when`; B: none
    assert(EnableOrder.violations(chirrtl) == Seq(EnableOrder.Violation("A", "early", "en")))
  }

  it should "declare each enable register before the registers it loads" in {
    check(
      "--robot",
      "planar3",
      "--clocks-per-sample",
      "3",
      "--schedule.cordic-units",
      "1",
      "--schedule.accumulate-slack",
      "2",
      "--bus",
      "none"
    )
    check(
      "--robot",
      "planar3",
      "--clocks-per-sample",
      "40",
      "--schedule.share-registers",
      "true",
      "--schedule.accumulate-slack",
      "8",
      "--datapath.registered-routes",
      "true",
      "--bus",
      "none"
    )
    check("--robot", "planar3")
    check(
      Seq("--robot", "golden/robots/ur5_robot.urdf", "--tip", "tool0", "--max-acceleration", "15") ++
        PayloadDesigns.scheduleArgs ++ Seq("--bus", "axi") ++
        Seq("--payload.enabled", "true", "--payload.max-mass", "5"): _*
    )
    check("--robot", "planar3", "--clocks-per-sample", "32", "--schedule.storage", "memory")
    check(
      "--robot",
      "planar3",
      "--clocks-per-sample",
      "4",
      "--datapath.registered-routes",
      "true",
      "--schedule.reader-copies",
      "true",
      "--bus",
      "none"
    )
  }
}
