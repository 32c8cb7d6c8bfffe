import reducerload.arm.{ArmConfig, ArmGolden}
import reducerload.graph.{ScheduleRequest, Storage}
object ScratchPanda extends App {
  val robot = args.headOption.getOrElse("panda")
  val iis = if (args.length > 1) args(1).split(",").map(_.toInt).toSeq else (80 to 152 by 4)
  val config = ArmGolden.of(robot).head.config
  for (c <- iis) {
    val t0 = System.nanoTime
    try { val p = ArmConfig(config.copy(targetError = Seq(1e-3), schedule = ScheduleRequest(clocksPerSample = Some(c), storage = Storage.Memory)))
    val b = p.banked.get
    println(f"$robot ii$c%4d latency ${p.latency}%4d depBound ${b.dependenceBound}%4d mul ${p.schedule.multiplierUnits} add ${b.adderUnits} blocks ${p.schedule.multiplierBlocks} copies ${b.copies.mkString(",")} (${(System.nanoTime - t0) / 1e9}%.1f s) ${b.latencyByOrder}")
    } catch { case e: IllegalArgumentException => println(s"$robot ii$c: ${e.getMessage.take(60)}") }
  }
}
