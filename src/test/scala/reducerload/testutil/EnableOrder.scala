package reducerload.testutil

/**
 * In a circuit's CHIRRTL, the registers loaded under a `when` on another register's value although declared
 * before that register. firtool 1.62 lowers registers in the order they are declared and keeps the `if` it
 * builds for each condition by the condition's value: the condition register of such a pair is lowered after
 * the `if` was made for it, and its old value's place can then be taken by another register's condition,
 * which finds the stale `if` and loads under the wrong enable. Which pair goes wrong changes from run to run
 * (the UR5 with accumulators: a root register loaded with its accumulator's enable in 3 of 6 runs of one
 * FIRRTL file), so the order is checked here, where it does not depend on the run.
 */
object EnableOrder {

  /** One register loaded under a later register's value: module, register, condition. */
  final case class Violation(module: String, register: String, condition: String)

  private val Module = """\s*module (\S+) :.*""".r
  private val Register = """\s*reg(?:reset)? (\S+) :.*""".r
  private val When = """(\s*)when (\S+) :.*""".r
  private val Connect = """\s*connect ([^,\s]+),.*""".r

  /** An open `when`: its indentation, and its condition when that is a register's value. */
  private final case class Open(indent: Int, register: Option[String])

  def violations(chirrtl: String): Seq[Violation] = {
    var module = ""
    var declared = Map.empty[String, Int]
    var open = List.empty[Open] // innermost first
    val found = Seq.newBuilder[Violation]
    chirrtl.linesIterator.foreach { line =>
      val indent = line.takeWhile(_ == ' ').length
      // a line at a `when`'s indentation closes it, unless it is that `when`'s `else`
      val isElse = line.trim.startsWith("else")
      open = open.dropWhile(w => indent < w.indent || (indent == w.indent && !isElse))
      line match {
        case Module(name)       => module = name; declared = Map.empty; open = Nil
        case Register(name)     => declared += name -> declared.size
        case When(spaces, cond) => open = Open(spaces.length, Some(cond).filter(declared.contains)) :: open
        case Connect(target) =>
          val register = target.takeWhile(c => c != '.' && c != '[')
          declared.get(register).foreach { at =>
            open
              .flatMap(_.register)
              .filter(declared(_) > at)
              .foreach(cond => found += Violation(module, register, cond))
          }
        case _ =>
      }
    }
    found.result().distinct
  }
}
