package reducerload.sim.replay

import reducerload.app.{Cli, Simulate}

import java.io.OutputStream

/**
 * By hand, not a test: the JVM side of `run simulate --engine model` alone, repeated in one JVM (the first
 * rounds warm up; the output goes nowhere), per CPU second of the replay thread: ./sbt "Test/runMain
 * reducerload.sim.replay.ReplayBenchmark FILE [ROUNDS] [simulate settings...]" e.g. on the bench script's
 * trajectory. One job, so the figures do not depend on the other core.
 */
object ReplayBenchmark {
  def main(args: Array[String]): Unit = {
    require(args.nonEmpty, "usage: ReplayBenchmark FILE [ROUNDS] [settings...]")
    val rounds = args.lift(1).filter(_.forall(_.isDigit)).map(_.toInt).getOrElse(5)
    val settings = args.drop(if (args.lift(1).exists(_.forall(_.isDigit))) 2 else 1).toSeq
    val cli = Cli.parse(
      "simulate",
      Seq("--input", args(0), "--output", "/dev/null", "--engine", "model", "--jobs", "1") ++ settings,
      Simulate.options,
      Simulate.flags
    )
    val request = Simulate.prepare(cli, cli.compiled)
    val nowhere = new OutputStream {
      def write(b: Int): Unit = (); override def write(b: Array[Byte], o: Int, l: Int): Unit = ()
    }
    (1 to rounds).foreach { round =>
      val s = Replay.run(
        request.design,
        None, // the model
        request.rows,
        1,
        nowhere,
        new ProgressLine(0, "", None)
      )
      val phases = s.phases.fold("")(p =>
        f"; per sample: codes ${p.codes / s.samples * 1e9}%.0f ns, model ${p.engine / s.samples * 1e9}%.0f ns, lines ${p.lines / s.samples * 1e9}%.0f ns"
      )
      println(
        f"round $round: ${s.samples} samples, ${s.samplesPerCpuSecond}%.0f samples per CPU second, ${s.samplesPerSecond}%.0f samples/s wall$phases"
      )
    }
  }
}
