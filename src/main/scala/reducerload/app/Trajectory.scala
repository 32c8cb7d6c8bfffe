package reducerload.app

import reducerload.util.{InputError, OutputFile}

import java.nio.file.Path
import scala.util.{Random, Try}

/**
 * `run trajectory`: a seeded random trajectory CSV for a design, every value within its declared range
 * (angles anywhere in [-pi, pi)), in the columns `simulate` reads. For benchmarks of `simulate`
 * (tools/bench-simulate); the values are written as Double.toString writes them, the longest decimal form a
 * CSV of doubles usually has.
 */
object Trajectory {
  val options: Seq[Opt] = Seq(
    Opt("output", "FILE", "the trajectory CSV to write"),
    Opt("samples", "N", "rows to write", "1000000"),
    Opt("seed", "S", "random seed (printed; rerun with it)", "1")
  )

  private def number[T](
      cli: Cli,
      name: String,
      default: T,
      parse: String => T,
      ok: T => Boolean,
      what: String
  ): T =
    cli.get(name) match {
      case None => default
      case Some(v) =>
        Try(parse(v)).toOption
          .filter(ok)
          .getOrElse(throw new InputError(s"command line: --$name must be $what, got '$v'"))
    }

  def run(cli: Cli): Unit = {
    val output: Path =
      cli.path("output").getOrElse(throw new InputError("command line: trajectory needs --output FILE"))
    val samples = number[Int](cli, "samples", 1000000, _.toInt, _ >= 1, "an integer >= 1")
    val seed = number[Long](cli, "seed", 1L, _.toLong, _ => true, "an integer")
    val design = Simulate.design(cli.compiled)
    val limit = Array.tabulate(design.columns.size)(c => design.limits.collectFirst { case (`c`, l) => l })
    val rng = new Random(seed)
    OutputFile.writeText(output) { out =>
      out.write(design.columns.mkString(","))
      out.write('\n')
      val line = new java.lang.StringBuilder(256)
      var i = 0 // a runtime loop counter
      while (i < samples) {
        line.setLength(0)
        var c = 0
        while (c < limit.length) {
          if (c > 0) line.append(',')
          val u = 2 * rng.nextDouble() - 1
          line.append(limit(c).fold(u * math.Pi)(u * _))
          c += 1
        }
        out.append(line).write('\n')
        i += 1
      }
    }
    println(
      s"wrote $output: $samples samples, seed $seed, columns ${design.columns.mkString(",")}, within the declared ranges"
    )
  }
}
