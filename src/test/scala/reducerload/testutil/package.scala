package reducerload

import reducerload.arm.ArmParams
import reducerload.compiler.Compiler
import reducerload.config.LoadParams

import scala.collection.concurrent.TrieMap

/** The golden arm traces live beside the arm code (the sweep measures against them too). */
package object testutil {
  type ArmGoldenTrace = reducerload.arm.ArmGoldenTrace
  val ArmGolden: reducerload.arm.ArmGolden.type = reducerload.arm.ArmGolden

  /** The monitored planar3 design the tests share (one Verilator build of it per test run). */
  val monitoredPlanar3: Seq[String] = reducerload.app.RegisterMapDoc.monitoredPlanar3

  private val compiled = TrieMap.empty[LoadParams, ArmParams]

  /** A configuration's datapath in the tests, compiled once per configuration ([[Compiler.arm]]). */
  implicit final class CompiledParams(private val p: LoadParams) extends AnyVal {
    def arm: ArmParams = compiled.getOrElseUpdate(p, Compiler.arm(p))
    def errorBound: Double = arm.errorBound
  }
}
