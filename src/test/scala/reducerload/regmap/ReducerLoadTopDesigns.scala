package reducerload.regmap

import reducerload.compiler.{Compiled, Compiler}
import reducerload.config.{GravitySettings, PayloadSettings}
import reducerload.graph.{ScheduleRequest, Storage}
import reducerload.testutil.ArmGolden

/** The designs the wrapper tests build (compiled once per JVM). */
object ReducerLoadTopDesigns {

  /**
   * The UR5 with a run-time payload and gravity at its shared block-RAM schedule (PayloadedArmSpec's
   * settings, docs/payload.md), without the monitor.
   */
  lazy val ur5Payloaded: Compiled = Compiler.compile(
    ArmGolden
      .of("ur5")
      .head
      .config
      .copy(
        payload = PayloadSettings(enabled = true, maxMass = 5.0),
        gravity = GravitySettings(runtime = true),
        schedule = ScheduleRequest(clocksPerSample = Some(88), storage = Some(Storage.Memory))
      ),
    "ReducerLoadTopDesigns.ur5Payloaded"
  )
}
