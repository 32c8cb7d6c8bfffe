package reducerload.testutil

import java.nio.file.{Files, Path}

/**
 * Temporary files and directories of a test run, all in one directory deleted when the test JVM exits (the
 * tests used to leave about a thousand entries in the system's temporary directory per run).
 */
object Scratch {
  private lazy val root: Path = {
    val dir = Files.createTempDirectory("reducer-load-tests-")
    sys.addShutdownHook(reducerload.sim.rtl.VerilatorHarness.deleteTree(dir))
    dir
  }

  /** A new empty directory. */
  def dir(prefix: String): Path = Files.createTempDirectory(root, prefix)

  /** A new empty file. */
  def file(prefix: String, suffix: String): Path = Files.createTempFile(root, prefix, suffix)
}
