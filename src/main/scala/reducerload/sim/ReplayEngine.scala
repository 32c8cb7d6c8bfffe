package reducerload.sim

/** What computes a replay's outputs: the RTL on a compiled Verilator harness, or the bit-accurate model. */
sealed trait ReplayEngine
object ReplayEngine {

  /** The emitted RTL, run by `harness` (one process per chunk, started from reset). */
  final case class Rtl(harness: CompiledHarness) extends ReplayEngine

  /** The bit-accurate model: for replays where the RTL has been proven equal to it. */
  case object Model extends ReplayEngine

  val names: Seq[String] = Seq("rtl", "model")
}
