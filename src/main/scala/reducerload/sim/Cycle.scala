package reducerload.sim

/** One clock cycle of stimulus for a streaming pipeline. */
sealed trait Cycle[+A]
object Cycle {
  final case class Sample[A](value: A) extends Cycle[A]
  case object Bubble extends Cycle[Nothing]
  case object Reset extends Cycle[Nothing]
}
