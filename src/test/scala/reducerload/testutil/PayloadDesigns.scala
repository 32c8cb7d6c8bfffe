package reducerload.testutil

import reducerload.config.{GravitySettings, LoadParams, PayloadSettings}
import reducerload.graph.{ScheduleRequest, Storage}

/** Settings of the payload designs more than one suite builds. */
object PayloadDesigns {

  /**
   * The UR5 with a run-time payload (up to 5 kg in tool0) and run-time gravity at its shared block-RAM
   * schedule (88 clocks per sample): PayloadedArmSpec's and the bus wrapper's tests' design
   * (docs/payload.md).
   */
  lazy val ur5: LoadParams = ArmGolden
    .of("ur5")
    .head
    .config
    .copy(
      payload = PayloadSettings(enabled = true, maxMass = 5.0),
      gravity = GravitySettings(runtime = true),
      schedule = ScheduleRequest(clocksPerSample = Some(88), storage = Some(Storage.Memory))
    )

  /**
   * `ur5`'s schedule as command-line settings: a UR5 built in a few seconds, where a test's design needs no
   * schedule of its own (without one, the device fit's search takes about 100 s).
   */
  val scheduleArgs: Seq[String] = Seq("--clocks-per-sample", "88", "--schedule.storage", "memory")
}
