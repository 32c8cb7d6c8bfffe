package reducerload.util

import java.nio.file.{Files, Path}

/** The checks every input file (trajectory, URDF, configuration) gets before it is read. */
object InputFile {

  /**
   * Why `p` cannot be read as an input file (a directory, nothing there, a device), naming the absolute path
   * where it was looked for; None when it is a regular file.
   */
  def problem(p: Path): Option[String] = {
    val where = p.toAbsolutePath.normalize
    if (Files.isDirectory(p)) Some(s"is a directory ($where), not a file")
    else if (!Files.exists(p)) Some(s"no such file (looked for $where)")
    else if (!Files.isRegularFile(p)) Some(s"not a regular file ($where)")
    else None
  }

  /** Refuse `p` unless it is a regular file; `source` names it in the message. */
  def check(p: Path, source: String): Unit = problem(p).foreach(why => throw new InputError(s"$source: $why"))
}
