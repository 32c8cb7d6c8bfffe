package reducerload.testutil

import chiseltest._
import firrtl2.AnnotationSeq
import reducerload.pipeline.MultiplierImpl

import scala.sys.process._
import scala.util.Try

/**
 * Which simulator runs the RTL tests: Verilator when it is on the PATH, the JVM simulator (treadle)
 * otherwise. `REDUCERLOAD_SIM=verilator` forces Verilator (and fails if it is missing);
 * `REDUCERLOAD_SIM=treadle` forces the JVM simulator.
 */
object SimBackend {
  private def verilatorOnPath: Boolean = Try(
    Seq("verilator", "--version").!!(ProcessLogger(_ => ()))
  ).isSuccess

  val name: String = sys.env.get("REDUCERLOAD_SIM").map(_.trim.toLowerCase) match {
    case Some("verilator") =>
      require(verilatorOnPath, "REDUCERLOAD_SIM=verilator but no verilator is on the PATH")
      "verilator"
    case Some("treadle") => "treadle"
    case Some(other) if other.nonEmpty =>
      throw new IllegalArgumentException(s"REDUCERLOAD_SIM must be verilator or treadle, got '$other'")
    case _ => if (verilatorOnPath) "verilator" else "treadle"
  }

  def isVerilator: Boolean = name == "verilator"

  val annotations: AnnotationSeq =
    if (isVerilator)
      Seq(
        VerilatorBackendAnnotation,
        chiseltest.simulator.VerilatorFlags(Seq("--x-assign", "fast", "--x-initial", "fast"))
      )
    else Seq(TreadleBackendAnnotation)

  /**
   * How the designs under test build their multiplies (import it where a test elaborates one): the Verilog
   * black box on Verilator; its Chisel twin on the JVM simulator, which cannot run Verilog.
   */
  implicit val multiplierImpl: MultiplierImpl =
    if (isVerilator) MultiplierImpl.VerilogBlackBox else MultiplierImpl.ChiselTwin

  /** The JVM simulator is ~100x slower: tests scale long streams down with this factor. */
  def scale(n: Int): Int = if (isVerilator) n else (n / 20).max(64)

  println(
    s"[sim] RTL tests run on $name" + (if (isVerilator) ""
                                       else
                                         " (install verilator or set REDUCERLOAD_SIM=verilator for full-length runs)")
  )
}

/** Seeds: fixed per test, overridable with REDUCERLOAD_SEED, always printed. */
object Seeds {
  def apply(testName: String, default: Long): Long = {
    val seed = sys.env.get("REDUCERLOAD_SEED").map(_.toLong).getOrElse(default)
    println(s"[seed] $testName: seed $seed (rerun with REDUCERLOAD_SEED=$seed)")
    seed
  }
}
