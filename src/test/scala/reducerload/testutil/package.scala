package reducerload

/** The golden arm traces live beside the arm code (the sweep measures against them too). */
package object testutil {
  type ArmGoldenTrace = reducerload.arm.ArmGoldenTrace
  val ArmGolden: reducerload.arm.ArmGolden.type = reducerload.arm.ArmGolden
}
