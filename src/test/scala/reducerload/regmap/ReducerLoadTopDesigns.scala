package reducerload.regmap

import reducerload.compiler.{Compiled, Compiler}
import reducerload.testutil.PayloadDesigns

/** The designs the wrapper tests build (compiled once per JVM). */
object ReducerLoadTopDesigns {

  /**
   * The UR5 with a run-time payload and gravity at its shared block-RAM schedule (PayloadedArmSpec's
   * settings, docs/payload.md), without the monitor.
   */
  lazy val ur5Payloaded: Compiled = Compiler.compile(PayloadDesigns.ur5, "ReducerLoadTopDesigns.ur5Payloaded")
}
