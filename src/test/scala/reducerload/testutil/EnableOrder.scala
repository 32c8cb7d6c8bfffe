package reducerload.testutil

/**
 * Registers a `when` on another register's value loads although they are declared before that register, in a
 * circuit's CHIRRTL. firtool 1.62 lowers registers in the order they are declared and keeps the `if` it
 * builds for each condition by the condition's value: the condition register of such a pair is lowered after
 * the `if` was made for it, and its old value's place can then be taken by another register's condition,
 * which finds the stale `if` and loads under the wrong enable. Which pair goes wrong changes from run to run
 * (the UR5 with accumulators: a root register loaded with its accumulator's enable in most runs of the same
 * FIRRTL), so the order is checked here, where it does not depend on the run.
 */
object EnableOrder {

  /** One register loaded under a later register's value: module, register, condition. */
  final case class Violation(module: String, register: String, condition: String)

  private val Module = """\s*module (\S+) :.*""".r
  private val Register = """\s*reg(?:reset)? (\S+) :.*""".r
  private val When = """(\s*)when (\S+) :.*""".r
  private val Else = """(\s*)else :.*""".r
  private val Connect = """\s*connect ([^,\s]+),.*""".r

  def violations(chirrtl: String): Seq[Violation] = {
    var module = ""
    var declared = Map.empty[String, Int]
    // the enclosing `when`s on a register: indentation, condition
    var open = List.empty[(Int, String)]
    val found = Seq.newBuilder[Violation]
    chirrtl.linesIterator.foreach { line =>
      val indent = line.takeWhile(_ == ' ').length
      val isElse = line.trim.startsWith("else")
      open = open.dropWhile { case (at, _) => indent < at || (indent == at && !isElse) }
      line match {
        case Module(name)   => module = name; declared = Map.empty; open = Nil
        case Register(name) => declared += name -> declared.size
        case When(spaces, cond) =>
          if (declared.contains(cond)) open = (spaces.length, cond) :: open
          else open = (spaces.length, "") :: open
        case Else(_) =>
        case Connect(target) =>
          val register = target.takeWhile(c => c != '.' && c != '[')
          declared.get(register).foreach { at =>
            open
              .collect { case (_, cond) if cond.nonEmpty && declared(cond) > at => cond }
              .foreach(cond => found += Violation(module, register, cond))
          }
        case _ =>
      }
    }
    found.result().distinct
  }
}
