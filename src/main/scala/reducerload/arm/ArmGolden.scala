package reducerload.arm

import reducerload.config.LoadParams
import reducerload.robot.{Mounting, RigidBody, RobotParams, SerialChain}
import reducerload.trace.TraceCsv

import java.nio.file.{Files, Paths}
import scala.jdk.CollectionConverters._

/**
 * A golden arm trace from golden/arms/ (the tests' references and the sweep's measured errors): samples,
 * Pinocchio's torques for every joint, and the configuration a user would write for its robot, ranges and
 * mounting (the `arm` preset with `--robot`, and `robot.base-rpy` from the line `# mounting:
 * base-rpy=r,p,y`).
 *
 * @param payloads
 *   per row, the payload the torques include (attached at `payloadRanges`' frame; mass 0: none), when the
 *   file has the payload columns ([[PayloadColumns]]); None on every row otherwise
 * @param payloadRanges
 *   the ranges the file declares its payloads within (line `# payload:`), when it has payload columns
 */
final case class ArmGoldenTrace(
    name: String,
    robot: String,
    config: LoadParams,
    chain: SerialChain,
    samples: IndexedSeq[ArmSample],
    torques: IndexedSeq[IndexedSeq[Double]],
    payloads: IndexedSeq[Option[RigidBody]],
    payloadRanges: Option[GoldenPayloadRanges]
) {
  def mounting: Mounting = config.robot.mounting
}

/**
 * The payload set a golden trace declares: the payload frame (a link the last moving joint carries), the
 * largest mass, the radius around the frame's origin the centre of mass stays within, and the bound of every
 * inertia tensor entry (about the centre of mass).
 */
final case class GoldenPayloadRanges(frame: String, maxMass: Double, comRadius: Double, maxInertia: Double)

object ArmGolden {
  val dir = Paths.get("golden", "arms")

  def load(file: String): ArmGoldenTrace = {
    val path = dir.resolve(file)
    val head = TraceCsv.read(path, Nil)
    val robot = head.commentFields("robot")
    val ranges = head.commentFields("ranges").map { case (k, v) => k -> v.split(",").toSeq.map(_.toDouble) }
    val source = if (robot("source") == "builtin") RobotParams.planar3 else robot("source")
    val mounting = head.commentFields("mounting").get("base-rpy").fold(Mounting.floor) { rpy =>
      val a = rpy.split(",").toSeq.map(_.toDouble)
      Mounting(a(0), a(1), a(2))
    }
    val config = LoadParams.arm.copy(robot =
      RobotParams(
        maxVelocity = ranges("vmax"),
        maxAcceleration = ranges("amax"),
        source = source,
        tip = robot.get("tip").filter(_ != "-").getOrElse(""),
        mounting = mounting
      )
    )
    val chain = config.robot.chain
    val n = chain.size
    val payloadRanges = Option(head.commentFields("payload")).filter(_.nonEmpty).map { p =>
      GoldenPayloadRanges(
        p("frame"),
        p("max-mass").toDouble,
        p("com-radius").toDouble,
        p("max-inertia").toDouble
      )
    }
    val payloadColumns = if (payloadRanges.isDefined) PayloadColumns.names else Nil
    val t = TraceCsv.read(path, ArmTrajectory.columns(n) ++ payloadColumns ++ (1 to n).map(j => s"tau$j"))
    val cols = ArmTrajectory.columns(n).map(t.column)
    val tau = (1 to n).map(j => t.column(s"tau$j"))
    val payload = payloadColumns.map(t.column)
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
      t.rows.indices.map(i => tau.map(_(i))),
      t.rows.indices.map(i => if (payload.isEmpty) None else Some(PayloadColumns.body(payload.map(_(i))))),
      payloadRanges
    )
  }

  /**
   * Every golden trace of one robot without payload, floor-mounted, in name order (the payload and mounting
   * traces are in the subdirectories below).
   */
  def of(robot: String): Seq[ArmGoldenTrace] = in("", robot)

  /** The traces of one robot carrying a payload (golden/arms/payload/). */
  def withPayload(robot: String): Seq[ArmGoldenTrace] = in("payload", robot)

  /** The traces of one robot on a tilted or ceiling mounting (golden/arms/mounting/). */
  def mounted(robot: String): Seq[ArmGoldenTrace] = in("mounting", robot)

  private def in(subdirectory: String, robot: String): Seq[ArmGoldenTrace] = {
    val files = Files
      .list(dir.resolve(subdirectory))
      .iterator()
      .asScala
      .map(_.getFileName.toString)
      .filter(f => f.startsWith(robot + "_") && f.endsWith(".csv"))
      .toSeq
      .sorted
    require(files.nonEmpty, s"no golden traces for $robot in ${dir.resolve(subdirectory)}")
    files.map(f => load(if (subdirectory.isEmpty) f else s"$subdirectory/$f"))
  }
}
