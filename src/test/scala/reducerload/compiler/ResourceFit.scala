package reducerload.compiler

/**
 * The LE prediction's coefficients fitted anew to the committed open-tool estimates (docs/sweep/arms.csv and
 * sweep.csv): least squares of the relative error, the fixed logic and the weights of
 * [[ResourceModel.LogicFeatures]] but the refinement's two (held and multiplexer bits, which the schedules
 * depend on). Prints them, the fit's errors and each point's prediction; ResourceModelSpec checks the ones in
 * the code. After a sweep re-run:
 *
 * {{{
 * ./sbt "Test/runMain reducerload.compiler.ResourceFit"
 * }}}
 */
object ResourceFit {
  def main(args: Array[String]): Unit = {
    val rows = ResourceModelSpec.rows
    // The first two weights are the refinement's (LogicCost: held and multiplexer bits), which its schedules
    // depend on: held at theirs; the fixed logic and the other weights are fitted.
    val held = Map(1 -> ResourceModel.coefficients(0), 2 -> ResourceModel.coefficients(1))
    val all = rows.map(r => (1.0 +: r.features.toSeq).map(_ / r.estLes).toArray).toArray
    val free = all.head.indices.filterNot(held.contains)
    val x = all.map(row => free.map(row).toArray)
    val y = all.map(row => 1.0 - held.map { case (i, w) => row(i) * w }.sum)
    val k = free.size
    // normal equations of min sum (x c - y)^2
    val a = Array.tabulate(k, k)((i, j) => x.map(row => row(i) * row(j)).sum)
    val b = Array.tabulate(k)(i => x.zip(y).map { case (row, t) => row(i) * t }.sum)
    val fitted = free.zip(solve(a, b)).toMap
    val c = all.head.indices.map(i => held.getOrElse(i, fitted.getOrElse(i, 0.0)))
    println(f"fixed ${c(0)}%.1f, per bit: ${c.tail.map(v => f"$v%.3f").mkString(", ")}")
    val predicted =
      rows.zip(all).map { case (r, row) => row.zip(c).map { case (v, w) => v * w }.sum * r.estLes }
    val errors = rows.zip(predicted).map { case (r, p) => (p - r.estLes) / r.estLes }
    println(
      f"${rows.size} points: rms ${100 * math.sqrt(errors.map(e => e * e).sum / errors.size)}%.1f %%, " +
        f"largest ${100 * errors.map(math.abs).max}%.1f %%"
    )
    rows.zip(predicted).zip(errors).foreach { case ((r, p), e) =>
      println(f"| ${r.source} | ${r.name} | ${r.estLes} | ${math.round(p)} | ${100 * e}%+.1f %% |")
    }
  }

  /** Gaussian elimination with partial pivoting. */
  private def solve(a0: Array[Array[Double]], b0: Array[Double]): Array[Double] = {
    val n = b0.length
    val a = a0.map(_.clone)
    val b = b0.clone
    for (col <- 0 until n) {
      val pivot = (col until n).maxBy(r => math.abs(a(r)(col)))
      val (ra, rb) = (a(col), b(col))
      a(col) = a(pivot); b(col) = b(pivot); a(pivot) = ra; b(pivot) = rb
      for (r <- col + 1 until n) {
        val f = a(r)(col) / a(col)(col)
        for (j <- col until n) a(r)(j) -= f * a(col)(j)
        b(r) -= f * b(col)
      }
    }
    val x = new Array[Double](n)
    for (r <- (0 until n).reverse) x(r) = (b(r) - (r + 1 until n).map(j => a(r)(j) * x(j)).sum) / a(r)(r)
    x
  }
}
