package reducerload.sim

/** A port in a Verilog module header: direction ("input", "output" or "inout") and width in bits. */
final case class VerilogPort(name: String, direction: String, width: Int)

/**
 * The port list of one module in firtool's output, read so the harness can check a port description before a
 * long C++ build (a wrong width would otherwise be masked silently). firtool writes one port per line and
 * leaves out the direction and range when they repeat the previous port's (`input clock,` then `reset,`), so
 * both carry over.
 */
object VerilogPortList {
  private val portLine =
    """^\s*(input|output|inout)?\s*(?:\[(\d+):(\d+)\])?\s*([A-Za-z_][A-Za-z0-9_$]*)\s*,?\s*(?://.*)?$""".r

  def apply(verilog: String, module: String): Seq[VerilogPort] = {
    val start = s"(?m)^\\s*module\\s+${java.util.regex.Pattern.quote(module)}\\s*\\(".r
      .findFirstMatchIn(verilog)
      .getOrElse(throw new IllegalArgumentException(s"the Verilog has no module '$module'"))
    val end = verilog.indexOf(");", start.end)
    require(end > 0, s"module '$module': the port list never ends")
    var direction = ""
    var width = 1
    verilog
      .substring(start.end, end)
      .linesIterator
      .map(_.trim)
      .filter(l => l.nonEmpty && !l.startsWith("//"))
      .map {
        case portLine(dir, hi, lo, name) =>
          if (dir != null) direction = dir
          if (dir != null || hi != null) width = if (hi == null) 1 else math.abs(hi.toInt - lo.toInt) + 1
          require(direction.nonEmpty, s"module '$module': port '$name' has no direction")
          VerilogPort(name, direction, width)
        case other =>
          throw new IllegalArgumentException(
            s"module '$module': cannot read the port line '$other' (one port per line expected, as firtool writes)"
          )
      }
      .toSeq
  }
}
