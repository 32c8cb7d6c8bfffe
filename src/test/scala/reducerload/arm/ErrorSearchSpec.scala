package reducerload.arm

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.graph.{ScheduleRequest, Ur5LatencyRecipe}
import reducerload.testutil.Seeds

/**
 * The derived error bound against an adversarial search ([[ErrorSearch]], in short): a search that finds an
 * error over a joint's bound shows the analysis unsound there.
 */
class ErrorSearchSpec extends AnyFlatSpec {
  "The UR5's derived error bounds" should "hold against an adversarial search for the largest error" in {
    val seed = Seeds("error-search-ur5", 81L)
    val p = Ur5LatencyRecipe(ScheduleRequest())
    val found = ErrorSearch(p, seed, samples = 600, climbs = 150)
    info(
      s"seed $seed: largest errors found / derived bounds per joint: " +
        found.map(f => f"${f.error}%.2e / ${f.bound}%.2e").mkString(", ")
    )
    found.zipWithIndex.foreach { case (f, j) =>
      assert(f.error > 0, s"joint ${j + 1}: the search found no error at all")
      assert(f.error <= f.bound, s"joint ${j + 1}: error ${f.error} at ${f.sample} over the bound ${f.bound}")
    }
  }
}
