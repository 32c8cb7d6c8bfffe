package reducerload.arm

import reducerload.config.LoadParams
import reducerload.robot.{RobotParams, SerialChain}
import reducerload.trace.TraceCsv

import java.nio.file.{Files, Paths}
import scala.jdk.CollectionConverters._

/**
 * A golden arm trace from golden/arms/ (the tests' references and the sweep's measured errors): samples,
 * Pinocchio's torques for every joint, and the configuration a user would write for its robot and ranges (the
 * `arm` preset with `--robot`).
 */
final case class ArmGoldenTrace(
    name: String,
    robot: String,
    config: LoadParams,
    chain: SerialChain,
    samples: IndexedSeq[ArmSample],
    torques: IndexedSeq[IndexedSeq[Double]]
)

object ArmGolden {
  val dir = Paths.get("golden", "arms")

  def load(file: String): ArmGoldenTrace = {
    val path = dir.resolve(file)
    val head = TraceCsv.read(path, Nil)
    val robot = head.commentFields("robot")
    val ranges = head.commentFields("ranges").map { case (k, v) => k -> v.split(",").toSeq.map(_.toDouble) }
    val source = if (robot("source") == "builtin") RobotParams.planar3 else robot("source")
    val config = LoadParams.arm.copy(robot =
      RobotParams(
        maxVelocity = ranges("vmax"),
        maxAcceleration = ranges("amax"),
        source = source,
        tip = robot.get("tip").filter(_ != "-").getOrElse("")
      )
    )
    val chain = config.robot.chain
    val n = chain.size
    val t = TraceCsv.read(path, ArmTrajectory.columns(n) ++ (1 to n).map(j => s"tau$j"))
    val cols = ArmTrajectory.columns(n).map(t.column)
    val tau = (1 to n).map(j => t.column(s"tau$j"))
    ArmGoldenTrace(
      file.stripSuffix(".csv"),
      robot("name"),
      config,
      chain,
      t.rows.indices.map { i =>
        val v = cols.map(_(i))
        ArmSample(
          v.slice(0, n).toIndexedSeq,
          v.slice(n, 2 * n).toIndexedSeq,
          v.slice(2 * n, 3 * n).toIndexedSeq
        )
      },
      t.rows.indices.map(i => tau.map(_(i)))
    )
  }

  /** Every golden trace of one robot, in name order. */
  def of(robot: String): Seq[ArmGoldenTrace] = {
    val files = Files
      .list(dir)
      .iterator()
      .asScala
      .map(_.getFileName.toString)
      .filter(f => f.startsWith(robot + "_") && f.endsWith(".csv"))
      .toSeq
      .sorted
    require(files.nonEmpty, s"no golden traces for $robot in $dir")
    files.map(load)
  }
}
