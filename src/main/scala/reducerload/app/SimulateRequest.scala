package reducerload.app

import reducerload.compiler.Compiled
import reducerload.config.LoadParams
import reducerload.sim.replay.{ReplayColumns, ReplayDesign, ReplayEngine, SampleRows}
import reducerload.trace.TraceTable

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

/**
 * A `run simulate` command line's checks done before the design is compiled: the trajectory (`table`, with
 * every column of `columns` a file must give) and where its payload comes from, the output file, the engine,
 * the job count and whether values beyond their ranges are clamped (`--saturate`).
 */
final case class SimulateInput(
    columns: ReplayColumns,
    table: TraceTable,
    payload: ReplayPayload,
    output: Path,
    engine: ReplayEngine,
    jobs: Int,
    saturate: Boolean
)
