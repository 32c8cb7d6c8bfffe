package reducerload.graph

import reducerload.arm.ArmParams
import reducerload.compiler.Compiler
import reducerload.testutil.ArmGolden

/**
 * The UR5 of the golden traces on the core of issue 33's latency recipe (1e-3 N·m, 18 clocks per sample, 66
 * blocks, placed by height, sums and products reassociated, registered routes), with the storage options a
 * spec asks for in `request` (its interval, blocks and order are the recipe's).
 */
object Ur5LatencyRecipe {
  private lazy val ur5 = ArmGolden.of("ur5").head.config

  def apply(request: ScheduleRequest): ArmParams = Compiler.arm(
    ur5.copy(
      targetError = Seq(1e-3),
      schedule = request
        .copy(clocksPerSample = Some(18), maxMultipliers = Some(66), listOrder = Some(ListOrder.ByHeight)),
      datapath = ur5.datapath.copy(reassociate = Reassociation.SumsAndProducts, registeredRoutes = Some(true))
    )
  )
}
