package reducerload.util

import java.util.concurrent.{Executors, ThreadFactory}
import scala.concurrent.duration.Duration
import scala.concurrent.{Await, ExecutionContext, Future}

/**
 * Work over consecutive chunks of `0 until total` on `jobs` threads of its own, results in chunk order. Exact
 * for a datapath with no state between samples: each chunk starts from reset.
 */
object ChunkedRun {
  def apply[R](total: Int, chunkSize: Int, jobs: Int, onChunkDone: Int => Unit = _ => ())(
      work: Range => R
  ): IndexedSeq[R] = {
    require(total >= 0, s"ChunkedRun: total must be >= 0, got $total")
    require(chunkSize >= 1, s"ChunkedRun: chunkSize must be >= 1, got $chunkSize")
    require(jobs >= 1, s"ChunkedRun: jobs must be >= 1, got $jobs")
    val chunks = (0 until total by chunkSize).map(start => start until (start + chunkSize).min(total))
    // Daemon threads: a failed run must not keep the JVM alive.
    val threads: ThreadFactory = r => { val t = new Thread(r, "chunked-run"); t.setDaemon(true); t }
    val pool = Executors.newFixedThreadPool(jobs, threads)
    val context = ExecutionContext.fromExecutorService(pool)
    try {
      val futures = chunks.map(c => Future { val r = work(c); onChunkDone(c.size); r }(context))
      futures.map(Await.result(_, Duration.Inf))
    } finally pool.shutdownNow()
  }
}
