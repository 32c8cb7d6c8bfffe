package reducerload.sim.replay

import reducerload.testutil.CompiledParams
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.arm.{ArmSample, LoadReference}
import reducerload.compiler.Compiler
import reducerload.dynamics.Rnea
import reducerload.sim.model.ReferenceTape
import reducerload.config.LoadParams
import reducerload.testutil.{ArmGolden, Seeds}

import scala.collection.immutable.ArraySeq
import scala.util.Random

/**
 * The replay in arrays ([[ArrayReplay]]: long codes, the long model, the reference as a [[DoubleTape]])
 * writes the same lines, errors and flags as the design's `encode`, `evaluate` and `result`, and the tapes
 * give the references' doubles bit for bit: for every joint-3 preset and every joint of planar3, the UR5 and
 * the Panda, on random rows in and beyond the declared ranges, signed zeros, rounding ties of the input codes
 * and large angles.
 */
class ReplayArraysSpec extends AnyFlatSpec {
  behavior of "the replay in arrays"

  private def rows(
      design: ReplayDesign[_, _],
      golden: Seq[IndexedSeq[Double]],
      rng: Random,
      fracBits: Int
  ): Seq[IndexedSeq[Double]] = {
    val width = design.columns.size
    val n = width / 3
    val limit = Array.fill(width)(3.0)
    design.limits.foreach { case (c, l) => limit(c) = l }
    val tie = 1 + math.scalb(1.0, -fracBits - 1)
    def random(scale: Double) = IndexedSeq.tabulate(width)(c => (rng.nextDouble() * 2 - 1) * limit(c) * scale)
    golden ++ Seq.fill(3000)(random(1.0)) ++ Seq.fill(300)(random(1.6)) ++ Seq(
      IndexedSeq.fill(width)(0.0),
      IndexedSeq.fill(width)(-0.0),
      IndexedSeq.tabulate(width)(c => if (c % 2 == 0) -0.0 else 0.0),
      IndexedSeq.tabulate(width)(c => if (c < n) -0.0 else 0.5),
      IndexedSeq.fill(width)(tie),
      IndexedSeq.fill(width)(-tie),
      IndexedSeq.tabulate(width)(c => if (c < n) 1e6 + c else 1e7),
      IndexedSeq.tabulate(width)(c => if (c < n) math.Pi * (c + 1) else -limit(c))
    )
  }

  private def check(label: String, design: ReplayDesign[_, _], rows: Seq[IndexedSeq[Double]]): Unit = {
    val fast = design.arrays.getOrElse(fail(s"$label: no replay in arrays"))
    val worker = fast.worker()
    val labels = design.errorLabels.size
    def old[In, Out](
        d: ReplayDesign[In, Out],
        i: Int,
        row: IndexedSeq[Double]
    ): (String, Seq[Double], Boolean) = {
      val text = new java.lang.StringBuilder
      val errors = new Array[Double](labels)
      val flagged = d.result(i.toLong, row, d.evaluate(d.encode(row)), text, errors)
      (text.toString, errors.toSeq, flagged)
    }
    val codes = new Array[Long](fast.inputCount)
    val out = new Array[Long](fast.outputCount)
    var flaggedRows = 0
    rows.zipWithIndex.foreach { case (row, i) =>
      val array = row.toArray
      // The row in the middle of a flat array, as the replay reads it.
      val flat = Array.fill(array.length)(Double.NaN) ++ array ++ Array.fill(array.length)(Double.NaN)
      worker.encode(flat, array.length, codes, 0)
      worker.evaluate(codes, 0, out, 0)
      val text = new java.lang.StringBuilder
      val errors = new Array[Double](labels)
      val flagged = worker.result(i.toLong, flat, array.length, out, 0, text, errors)
      val expected = old(design, i, ArraySeq.unsafeWrapArray(array))
      assert((text.toString, errors.toSeq, flagged) == expected, s"$label: row $i (${row.mkString(",")})")
      if (flagged) flaggedRows += 1
    }
    assert(flaggedRows > 0 && flaggedRows < rows.size, s"$label: $flaggedRows of ${rows.size} rows flagged")
  }

  it should "write the design's lines for every joint-3 preset" in {
    val rng = new Random(Seeds("replay-arrays-joint3", 71L))
    LoadParams.presets.foreach { case (name, p) =>
      val design = new LoadReplay(p, p.arm)
      check(s"preset $name", design, rows(design, Nil, rng, p.arm.numerics.velocityPortFormat.fracBits))
    }
  }

  it should "write the design's lines for every joint of planar3, the UR5 and the Panda" in {
    val rng = new Random(Seeds("replay-arrays-arm", 72L))
    Seq("planar3", "ur5", "panda").foreach { robot =>
      val traces = ArmGolden.of(robot)
      val p = Compiler.arm(traces.head.config)
      val design = new ArmReplay(p)
      check(
        robot,
        design,
        rows(
          design,
          traces.flatMap(_.samples).take(500).map(_.toSeq),
          rng,
          p.numerics.velocityPortFormat.fracBits
        )
      )
    }
  }

  it should "give the references' doubles bit for bit (DoubleTape)" in {
    val rng = new Random(Seeds("replay-arrays-tape", 73L))
    def same(a: Double, b: Double) =
      java.lang.Double.doubleToRawLongBits(a) == java.lang.Double.doubleToRawLongBits(b)
    def row(width: Int) = Array.fill(width)(rng.nextInt(8) match {
      case 0 => -0.0
      case 1 => 0.0
      case _ => (rng.nextDouble() * 2 - 1) * math.pow(10, rng.nextInt(6) - 2)
    })
    LoadParams.presets.foreach { case (name, p) =>
      val tape = ReferenceTape.joint3(p.robot, p.model)
      val v = tape.tape.scratch()
      (0 until 5000).foreach { _ =>
        val r = row(9)
        tape.evaluate(r, v)
        val expected = LoadReference.torque(p.robot, p.model, ArmSample.fromRow(r.toIndexedSeq))
        assert(same(tape.tape.output(v, 0), expected), s"preset $name at ${r.mkString(",")}")
      }
    }
    Seq("planar3", "ur5", "panda").foreach { robot =>
      val chain = Compiler.arm(ArmGolden.of(robot).head.config).chain
      val tape = ReferenceTape.rnea(chain)
      val v = tape.tape.scratch()
      val n = chain.size
      (0 until 2000).foreach { _ =>
        val r = row(3 * n)
        tape.evaluate(r, v)
        val expected = Rnea.reference(
          chain,
          r.slice(0, n).toIndexedSeq,
          r.slice(n, 2 * n).toIndexedSeq,
          r.slice(2 * n, 3 * n).toIndexedSeq
        )
        assert(
          (0 until n).forall(j => same(tape.tape.output(v, j), expected(j))),
          s"$robot at ${r.mkString(",")}"
        )
      }
    }
  }
}
