package reducerload.testutil

import reducerload.arm.{ArmSample, ArmTrajectory}
import reducerload.load.RobotParams
import reducerload.robot.{Planar3, SerialChain, Urdf}
import reducerload.trace.TraceCsv

import java.nio.file.{Files, Paths}
import scala.jdk.CollectionConverters._

/** A golden arm trace from golden/arms/: samples, Pinocchio's torques for every joint, and the robot and ranges it is for. */
final case class ArmGoldenTrace(name: String, robot: String, chain: SerialChain, maxVelocity: Seq[Double], maxAcceleration: Seq[Double],
  samples: IndexedSeq[ArmSample], torques: IndexedSeq[IndexedSeq[Double]])

object ArmGolden {
  val dir = Paths.get("golden", "arms")

  def load(file: String): ArmGoldenTrace = {
    val path = dir.resolve(file)
    val head = TraceCsv.read(path, Nil)
    val robot = head.commentFields("robot")
    val ranges = head.commentFields("ranges").map { case (k, v) => k -> v.split(",").toSeq.map(_.toDouble) }
    val chain =
      if (robot("source") == "builtin") Planar3.chain(RobotParams())
      else Urdf.read(Paths.get(robot("source")), robot.get("tip").filter(_ != "-"))
    val n = chain.size
    val t = TraceCsv.read(path, ArmTrajectory.columns(n) ++ (1 to n).map(j => s"tau$j"))
    val cols = ArmTrajectory.columns(n).map(t.column)
    val tau = (1 to n).map(j => t.column(s"tau$j"))
    ArmGoldenTrace(file.stripSuffix(".csv"), robot("name"), chain, ranges("vmax"), ranges("amax"),
      t.rows.indices.map { i =>
        val v = cols.map(_(i))
        ArmSample(v.slice(0, n).toIndexedSeq, v.slice(n, 2 * n).toIndexedSeq, v.slice(2 * n, 3 * n).toIndexedSeq)
      },
      t.rows.indices.map(i => tau.map(_(i))))
  }

  /** Every golden trace of one robot, in name order. */
  def of(robot: String): Seq[ArmGoldenTrace] = {
    val files = Files.list(dir).iterator().asScala.map(_.getFileName.toString).filter(f => f.startsWith(robot + "_") && f.endsWith(".csv")).toSeq.sorted
    require(files.nonEmpty, s"no golden traces for $robot in $dir")
    files.map(load)
  }
}
