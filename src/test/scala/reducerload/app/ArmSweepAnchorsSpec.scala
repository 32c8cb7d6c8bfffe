package reducerload.app

import org.scalatest.flatspec.AnyFlatSpec

/**
 * The README's FPGA-beside-CPU rows: of the points that fit an EP4CE30, only designs that route on the clock
 * proxy are anchors (registers storage above 4 clocks per sample only with registered routes and no product
 * forwarded past them).
 */
class ArmSweepAnchorsSpec extends AnyFlatSpec {
  behavior of "the arm sweep's CPU anchors"

  /** A row of arms.csv with the columns the anchors read; the rest blank. */
  private def row(schedule: String, storage: String, clocks: Int, rate: Double, latencyNs: Int, les: Int) =
    ArmSweep.header.map {
      case "robot"             => "ur5"
      case "schedule"          => schedule
      case "storage"           => storage
      case "clocks_per_sample" => clocks.toString
      case "latency_cycles"    => "147" // read only by the detail column
      case "latency_ns"        => latencyNs.toString
      case "samples_per_s"     => rate.toString
      case "mult_blocks"       => "63"
      case "est_les"           => les.toString
      case "est_m9k"           => "7"
      case "max_error_nm"      => "2.53e-04"
      case _                   => ""
    }
  private val cpu = Seq(
    Seq("robot", "engine", "us_per_call", "calls_per_s", "operations", "machine"),
    Seq("ur5", "generated-c", "0.21", "4.8e6", "506", "test")
  )
  private def fpgaRows(arms: Seq[Seq[String]]) =
    ArmSweep.anchors(ArmSweep.header +: arms, cpu, detail = false).filter(_.contains("EP4CE30"))

  it should "leave out registers designs above 4 clocks per sample with direct routes or forwarded products" in {
    val rows = fpgaRows(
      Seq(
        row("fast66-t1e-3", "registers", 17, 8.82e6, 727, 14731), // direct at 17 clocks: does not route
        row("routed66-t1e-3", "registers", 17, 8.82e6, 980, 23693),
        row("latency66-t1e-3", "registers", 18, 8.33e6, 767, 22749), // products forwarded: did not route
        row("mem-ii88-t1e-3", "memory", 88, 1.70e6, 1553, 8400),
        row("budget66", "registers", 4, 3.0e6, 500, 20000), // direct at 4 clocks: routes
        row("no-such-point", "registers", 10, 9.9e6, 400, 9000) // unknown: counted as direct
      )
    )
    assert(
      rows == Seq(
        "| ur5 | EP4CE30, `routed66-t1e-3` | 8.82 M | 0.98 |",
        "| ur5 | EP4CE30, `budget66` | 3.00 M | 0.50 |"
      ),
      rows.mkString("\n")
    )
  }

  it should "know a point's rows of several seeds by their -sN" in {
    assert(ArmSweep.pointOf("routed66-t1e-3-s2").map(_.name).contains("routed66-t1e-3"))
    assert(ArmSweep.pointOf("routed66-t1e-3-sx").isEmpty && ArmSweep.pointOf("ii1").nonEmpty)
    val rows = fpgaRows(Seq(row("routed66-t1e-3-s2", "registers", 17, 8.4e6, 1030, 23693)))
    assert(rows == Seq("| ur5 | EP4CE30, `routed66-t1e-3-s2` | 8.40 M | 1.03 |"), rows.mkString("\n"))
  }
}
