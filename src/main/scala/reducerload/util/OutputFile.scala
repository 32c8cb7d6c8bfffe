package reducerload.util

import java.io.{BufferedOutputStream, BufferedWriter, IOException, OutputStream, OutputStreamWriter, Writer}
import java.nio.charset.StandardCharsets
import java.nio.file.attribute.PosixFilePermission
import java.nio.file.{AccessDeniedException, Files, Path, StandardCopyOption, StandardOpenOption}
import scala.util.Random

/**
 * Every file the generator writes for its user (emit's files, simulate's CSV and summary, trajectories, sweep
 * tables), written one way:
 *
 *   - all or nothing: into a temporary file beside the target (same directory, so the same file system), then
 *     renamed over it atomically; a failure leaves the old file, or none, and no temporary;
 *   - an existing file whose owner-write permission bit is clear (chmod a-w, 0444) is not replaced: one line,
 *     nothing written. The bit, not `Files.isWritable`: root may write anything, and CI runs as root, so the
 *     rule would otherwise differ between a developer's machine and CI. Where the file system has no POSIX
 *     bits, `Files.isWritable` decides;
 *   - the mode is the user's umask's, for a new file and a replaced one alike (the temporary is created like
 *     any new file, never with `Files.createTempFile`'s 0600; a replaced file does not keep its old mode);
 *   - a symbolic link to an existing file is followed: the file it points to is replaced, the link stays.
 */
object OutputFile {

  /** Refuse, before anything is written, a target that cannot be replaced; see the object's rules. */
  def check(path: Path): Unit = {
    val abs = target(path)
    if (Files.isDirectory(abs)) throw new InputError(s"$path: is a directory (an output file was expected)")
    val parent = abs.getParent
    if (parent != null && !Files.isDirectory(parent))
      throw new InputError(s"$path: directory $parent does not exist")
    if (Files.exists(abs) && readOnly(abs))
      throw new InputError(s"$path: exists and is read-only; not replaced (make it writable or remove it)")
  }

  /** The file `path` names: the absolute path, or where a symbolic link to an existing file points. */
  private def target(path: Path): Path = {
    val abs = path.toAbsolutePath.normalize
    if (Files.isSymbolicLink(abs) && Files.exists(abs)) abs.toRealPath() else abs
  }

  /** The owner-write bit is clear (or, without POSIX bits, the file is not writable). */
  def readOnly(path: Path): Boolean =
    try !Files.getPosixFilePermissions(path).contains(PosixFilePermission.OWNER_WRITE)
    catch { case _: UnsupportedOperationException => !Files.isWritable(path) }

  /** Write `path` through `body`, all or nothing; returns what `body` returns. */
  def write[T](path: Path)(body: OutputStream => T): T = {
    check(path)
    val abs = target(path)
    val tmp = temporaryBeside(abs)
    try {
      val out = new BufferedOutputStream(Files.newOutputStream(tmp, StandardOpenOption.WRITE), 1 << 20)
      val result =
        try body(out)
        finally out.close()
      Files.move(tmp, abs, StandardCopyOption.REPLACE_EXISTING, StandardCopyOption.ATOMIC_MOVE)
      result
    } finally Files.deleteIfExists(tmp)
  }

  /** [[write]] through a UTF-8 writer. */
  def writeText[T](path: Path)(body: Writer => T): T = write(path) { out =>
    val writer = new BufferedWriter(new OutputStreamWriter(out, StandardCharsets.UTF_8), 1 << 16)
    val result = body(writer)
    writer.flush()
    result
  }

  /** [[write]] of a string, UTF-8. */
  def writeString(path: Path, text: String): Unit =
    write(path)(_.write(text.getBytes(StandardCharsets.UTF_8)))

  /**
   * Several files of one directory, all or none: every target is checked first, all are written to
   * temporaries, then each is renamed in (a failure before the renames leaves every old file as it was).
   * Returns the written paths.
   */
  def writeAll(dir: Path, files: Seq[(String, String)]): Seq[Path] = {
    val abs = dir.toAbsolutePath.normalize
    if (Files.exists(abs) && !Files.isDirectory(abs))
      throw new InputError(s"$dir: exists and is not a directory")
    val targets = files.map { case (name, _) => target(abs.resolve(name)) }
    if (Files.isDirectory(abs)) targets.foreach(check)
    else
      try Files.createDirectories(abs)
      catch {
        case e: IOException => throw new InputError(s"$dir: cannot create the directory (${reason(e)})")
      }
    val temporaries = collection.mutable.ArrayBuffer.empty[Path]
    try {
      files.zip(targets).foreach { case ((_, text), target) =>
        val tmp = temporaryBeside(target)
        temporaries += tmp
        Files.write(tmp, text.getBytes(StandardCharsets.UTF_8), StandardOpenOption.WRITE)
      }
      temporaries.toSeq.zip(targets).map { case (tmp, target) =>
        Files.move(tmp, target, StandardCopyOption.REPLACE_EXISTING, StandardCopyOption.ATOMIC_MOVE)
      }
    } finally temporaries.foreach(Files.deleteIfExists)
  }

  /**
   * A new empty file beside `target`, created as any new file is (its mode from the umask), under a name no
   * other file has (`.<name>.partial-<random>`).
   */
  private def temporaryBeside(target: Path): Path = {
    val parent = target.getParent
    @annotation.tailrec
    def attempt(left: Int): Path = {
      val tmp = parent.resolve(s".${target.getFileName}.partial-${Random.alphanumeric.take(8).mkString}")
      val created =
        try Some(Files.createFile(tmp))
        catch {
          case _: java.nio.file.FileAlreadyExistsException if left > 0 => None
          case e: AccessDeniedException =>
            throw new InputError(s"$target: cannot write in directory $parent (${reason(e)})")
        }
      created match {
        case Some(p) => p
        case None    => attempt(left - 1)
      }
    }
    attempt(8)
  }

  private def reason(e: IOException): String = e match {
    case _: AccessDeniedException => "permission denied"
    case _                        => Option(e.getMessage).getOrElse(e.getClass.getSimpleName)
  }
}
