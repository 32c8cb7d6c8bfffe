package reducerload.util

import java.nio.file.{Files, Path}

/** The checks every input file (trajectory, URDF, configuration) gets before it is read. */
object InputFile {

  /**
   * Refuse `p` unless it is a regular file (a directory, nothing there, a device), naming it by `source` and,
   * when `source` does not already say it, by the absolute path where it was looked for.
   */
  def check(p: Path, source: String): Unit = {
    val where = p.toAbsolutePath.normalize.toString
    def at(what: String, how: String) = if (source.contains(where)) what else s"$what ($how $where)"
    val problem =
      if (Files.isDirectory(p)) Some(at("is a directory, not a file", "at"))
      else if (!Files.exists(p)) Some(at("no such file", "looked for"))
      else if (!Files.isRegularFile(p)) Some(at("not a regular file", "at"))
      else None
    problem.foreach(why => throw new InputError(s"$source: $why"))
  }
}
