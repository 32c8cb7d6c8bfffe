package reducerload.app

import reducerload.compiler.Compiled
import reducerload.config.LoadParams
import reducerload.sim.replay.{ReplayDesign, ReplayEngine, SampleRows}

import java.nio.file.Path

/**
 * A `run simulate` command line with every check done: the compiled design, its replay, the trajectory's rows
 * (values in `design.columns` order, flat), the output file, the engine and the job count.
 */
final case class SimulateRequest[In, Out](
    compiled: Compiled,
    design: ReplayDesign[In, Out],
    rows: SampleRows,
    output: Path,
    engine: ReplayEngine,
    jobs: Int
) {
  def params: LoadParams = compiled.config
}
