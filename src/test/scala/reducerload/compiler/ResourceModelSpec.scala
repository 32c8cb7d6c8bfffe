package reducerload.compiler

import org.scalatest.flatspec.AnyFlatSpec
import org.scalatest.matchers.should.Matchers
import reducerload.app.{ArmSweep, Sweep}
import reducerload.arm.{ArmGolden, ArmParams}
import reducerload.config.DeviceFamily

import java.nio.file.{Files, Paths}
import java.util.concurrent.Executors
import scala.concurrent.duration.Duration
import scala.concurrent.{Await, ExecutionContext, Future}
import scala.jdk.CollectionConverters._

/**
 * The resource prediction against the committed open-tool estimates (docs/sweep/arms.csv, sweep.csv): the
 * memory blocks counted from the structures, the logic cells from the calibrated count. Prints the table
 * docs/device.md quotes: `REDUCERLOAD_ALL_POINTS=1 ./sbt "testOnly reducerload.compiler.ResourceModelSpec"`.
 * Without `REDUCERLOAD_ALL_POINTS=1` (so in `./sbt test`) it checks a short form: planar3's points, the UR5's
 * at the default refinement and its `parallel66-t1e-3` (the README's latency recipe), and two of the Panda's
 * (one per storage). The others take 10-90 s each to schedule (the UR5's and Panda's refined with the sweep's
 * fast refinement the most): with them its first test took about 6 minutes of a CI run on two cores.
 */
class ResourceModelSpec extends AnyFlatSpec with Matchers {
  import ResourceModelSpec._

  "the memory-block count" should "agree with the open-tool estimate's M9K count on the committed arm points" in {
    // Registers storage (CORDIC tables and block-RAM delays): exactly; memory storage (banks and the
    // microcode table, counted before the table shares equal fields): within one block, but for the
    // five-adder point, whose table the synthesis shares more of (more still since the multipliers' operand
    // shifts have select fields of their own).
    tested.filter(_.source == "arms").foreach { pt =>
      val est = pt.estM9k.get
      val tol =
        if (pt.p.banked.isEmpty) (if (pt.p.schedule.clocksPerSample == 1) est / 10 else 1)
        else if (pt.name.contains("-a5-")) est / 2
        else 1
      withClue(pt.name)(math.abs(pt.m9k - est) should be <= tol)
    }
  }

  "the logic-cell prediction" should s"be within ${ResourceModel.logicTolerance} of the open-tool estimate" in {
    println("source,point,est_les,predicted_les,err_percent,est_m9k,predicted_m9k")
    tested.foreach { r =>
      println(
        Seq(
          r.source,
          r.name,
          r.estLes,
          r.les,
          f"${100.0 * (r.les - r.estLes) / r.estLes}%+.1f",
          r.estM9k.getOrElse(""),
          r.m9k
        )
          .mkString(",")
      )
    }
    val errors = tested.map(r => (r.les - r.estLes).toDouble / r.estLes)
    val rms = math.sqrt(errors.map(e => e * e).sum / errors.size)
    println(
      f"${tested.size} points: rms ${100 * rms}%.1f %%, largest ${100 * errors.map(math.abs).max}%.1f %%"
    )
    errors.foreach(e => math.abs(e) should be <= ResourceModel.logicTolerance)
    rms should be <= 0.07
  }
}

object ResourceModelSpec {
  final case class Point(source: String, name: String, p: ArmParams, estLes: Int, estM9k: Option[Int]) {
    lazy val features = ResourceModel.features(p)
    lazy val m9k = ResourceModel.memories(p).map(_.blocks(DeviceFamily.CycloneIVE)).sum
    lazy val les = ResourceModel.logicElements(p)
    def cells: Seq[String] =
      Seq(source, name, estLes.toString, les.toString, estM9k.fold("")(_.toString), m9k.toString) ++
        features.toSeq.map(f => f"$f%.0f")
  }

  private def csv(file: String): Seq[Map[String, String]] = {
    val lines = Files.readAllLines(Paths.get(file)).asScala.toSeq
    val header = lines.head.split(",").toSeq
    lines.tail.map(l => header.zip(l.split(",", -1).toSeq).toMap)
  }

  /**
   * The points, each compiled and scheduled on every core: the points share nothing, and their compilation
   * (fraction bits fitted to a target, schedules refined) is most of this suite's time.
   */
  private def built[A](items: Seq[A])(point: A => Point): Seq[Point] = {
    val pool = Executors.newFixedThreadPool(Runtime.getRuntime.availableProcessors)
    implicit val ec: ExecutionContext = ExecutionContext.fromExecutorService(pool)
    try
      Await.result(
        Future.traverse(items)(a => Future { val pt = point(a); pt.m9k; pt.les; pt }),
        Duration.Inf
      )
    finally pool.shutdown()
  }

  private def armPoints(keep: (String, ArmSweep.Point) => Boolean): Seq[Point] =
    built(csv("docs/sweep/arms.csv").filter(row => keep(row("robot"), schedule(row)))) { row =>
      val robot = row("robot")
      val p = Compiler.arm(schedule(row).config(ArmGolden.of(robot).head.config))
      Point("arms", s"$robot ${row("schedule")}", p, row("est_les").toInt, Some(row("est_m9k").toInt))
    }
  private def schedule(row: Map[String, String]): ArmSweep.Point =
    ArmSweep.schedules.find(_.name == row("schedule")).get

  lazy val sweepPoints: Seq[Point] = built(csv("docs/sweep/sweep.csv")) { row =>
    val p = Compiler.arm(Sweep.grid.find(_._1 == row("config")).get._2)
    Point("sweep", row("config"), p, row("est_les").toInt, None)
  }

  /** Every committed point (the fit, [[ResourceFit]]). */
  lazy val rows: Seq[Point] = armPoints((_, _) => true) ++ sweepPoints

  /** The points of the short form (above) beyond planar3's and the UR5's at the default refinement. */
  private val shortForm: Map[String, Set[String]] =
    Map("ur5" -> Set("parallel66-t1e-3"), "panda" -> Set("budget66", "mem-ii88-t1e-3"))
  // a renamed sweep point would leave the short form without a word
  shortForm.values.flatten.foreach(name =>
    require(ArmSweep.schedules.exists(_.name == name), s"ResourceModelSpec: no sweep point '$name'")
  )

  /** The points the spec checks: all with `REDUCERLOAD_ALL_POINTS=1`, else the short form (above). */
  lazy val tested: Seq[Point] =
    if (sys.env.get("REDUCERLOAD_ALL_POINTS").contains("1")) rows
    else
      armPoints((robot, point) =>
        robot == "planar3" || (robot == "ur5" && point.request.refinement < ArmSweep.fastRefinement) ||
          shortForm.get(robot).exists(_(point.name))
      ) ++ sweepPoints
}
