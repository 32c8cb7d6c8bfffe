package reducerload.testutil

import reducerload.arm.ArmSample
import reducerload.load.Joint3Columns
import reducerload.robot.RobotParams
import reducerload.trace.TraceCsv

import java.nio.file.{Files, Paths}
import scala.jdk.CollectionConverters._

/** A golden trace from golden/: samples and the loads an independent reference computed. */
final case class GoldenTrace(
    name: String,
    robot: RobotParams,
    samples: IndexedSeq[ArmSample],
    rnea: IndexedSeq[Double],
    exact: IndexedSeq[Double],
    paper: IndexedSeq[Double]
)

object Golden {
  val dir = Paths.get("golden")
  val columns: Seq[String] = Joint3Columns.names ++ Seq("tau3_rnea", "tau3_exact", "tau3_paper")

  def load(file: String): GoldenTrace = {
    val t = TraceCsv.read(dir.resolve(file), columns)
    val r = t.commentFields("robot").map { case (k, v) => k -> v.toDouble }
    val ranges = t.commentFields("ranges").map { case (k, v) => k -> v.toDouble }
    val robot = RobotParams(
      r("m3"),
      r("l1"),
      r("l2"),
      r("l3"),
      r("g"),
      Seq.fill(3)(ranges("dmax")),
      Seq.fill(3)(ranges("ddmax"))
    )
    val cols = Joint3Columns.names.map(t.column)
    GoldenTrace(
      file.stripSuffix(".csv"),
      robot,
      t.rows.indices.map(i => ArmSample.fromRow(cols.map(_(i)))),
      t.column("tau3_rnea"),
      t.column("tau3_exact"),
      t.column("tau3_paper")
    )
  }

  /** Every golden trace, in name order. */
  def all: Seq[GoldenTrace] = {
    val files =
      Files.list(dir).iterator().asScala.map(_.getFileName.toString).filter(_.endsWith(".csv")).toSeq.sorted
    require(files.nonEmpty, s"no golden traces in $dir")
    files.map(load)
  }
}
