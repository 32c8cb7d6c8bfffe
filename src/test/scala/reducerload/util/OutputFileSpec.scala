package reducerload.util

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.testutil.Scratch

import java.nio.charset.StandardCharsets
import java.nio.file.attribute.PosixFilePermissions
import java.nio.file.{Files, Path}
import scala.jdk.CollectionConverters._

class OutputFileSpec extends AnyFlatSpec {
  behavior of "OutputFile"

  private def read(p: Path): String = new String(Files.readAllBytes(p), StandardCharsets.UTF_8)
  private def mode(p: Path): String = PosixFilePermissions.toString(Files.getPosixFilePermissions(p))

  /** The mode the user's umask gives a new file: that of a file created the ordinary way. */
  private def umaskMode(dir: Path): String = {
    val plain = Files.createFile(dir.resolve("plain"))
    try mode(plain)
    finally Files.delete(plain)
  }

  private def listing(dir: Path): Seq[String] =
    Files.list(dir).iterator.asScala.map(_.getFileName.toString).toSeq.sorted

  it should "give new and replaced files the umask's mode, not a temporary file's 0600" in {
    val dir = Scratch.dir("out-mode-")
    val expected = umaskMode(dir)
    // The umask as the shell reports it, for the record (0022 gives rw-r--r--).
    val umask = scala.sys.process.Process(Seq("sh", "-c", "umask")).!!.trim
    info(s"umask $umask: new files $expected")
    val f = dir.resolve("a.csv")
    OutputFile.writeString(f, "one\n")
    assert(mode(f) == expected)
    Files.setPosixFilePermissions(f, PosixFilePermissions.fromString("rw-------"))
    OutputFile.writeString(f, "two\n")
    assert(read(f) == "two\n")
    assert(mode(f) == expected, "a replaced file takes the umask's mode")
    assert(listing(dir) == Seq("a.csv"), "a temporary file was left behind")
  }

  it should "refuse to replace a file whose owner-write bit is clear, as root too, writing nothing" in {
    val dir = Scratch.dir("out-readonly-")
    val f = dir.resolve("loads.csv")
    Files.write(f, "keep\n".getBytes(StandardCharsets.UTF_8))
    Files.setPosixFilePermissions(f, PosixFilePermissions.fromString("r--r--r--"))
    val e = intercept[InputError](OutputFile.writeString(f, "new\n"))
    assert(e.getMessage.contains(f.toString) && e.getMessage.contains("read-only"), e.getMessage)
    assert(!e.getMessage.contains("\n"))
    assert(read(f) == "keep\n")
    assert(listing(dir) == Seq("loads.csv"))
    // A directory where a file is expected.
    val d = Files.createDirectory(dir.resolve("sub"))
    assert(intercept[InputError](OutputFile.writeString(d, "x")).getMessage.contains("is a directory"))
  }

  it should "write several files all or none: one read-only target leaves every file as it was" in {
    val dir = Scratch.dir("out-all-")
    Files.write(dir.resolve("b.md"), "old b".getBytes(StandardCharsets.UTF_8))
    Files.setPosixFilePermissions(dir.resolve("b.md"), PosixFilePermissions.fromString("r--r--r--"))
    val e = intercept[InputError](OutputFile.writeAll(dir, Seq("a.sv" -> "new a", "b.md" -> "new b")))
    assert(e.getMessage.contains("b.md") && e.getMessage.contains("read-only"), e.getMessage)
    assert(listing(dir) == Seq("b.md") && read(dir.resolve("b.md")) == "old b")
    Files.setPosixFilePermissions(dir.resolve("b.md"), PosixFilePermissions.fromString("rw-r--r--"))
    val written = OutputFile.writeAll(dir, Seq("a.sv" -> "new a", "b.md" -> "new b"))
    assert(written.map(_.getFileName.toString) == Seq("a.sv", "b.md"))
    assert(read(dir.resolve("a.sv")) == "new a" && read(dir.resolve("b.md")) == "new b")
    assert(written.forall(p => mode(p) == umaskMode(dir)))
  }

  it should "replace the file a symbolic link points to, keeping the link" in {
    val dir = Scratch.dir("out-link-")
    val real = dir.resolve("real.csv")
    OutputFile.writeString(real, "old\n")
    val link = Files.createSymbolicLink(dir.resolve("link.csv"), real.getFileName)
    OutputFile.writeString(link, "new\n")
    assert(Files.isSymbolicLink(link) && read(real) == "new\n")
    assert(listing(dir) == Seq("link.csv", "real.csv"))
  }

  it should "keep the old file and leave no temporary when writing fails midway" in {
    val dir = Scratch.dir("out-fail-")
    val f = dir.resolve("t.csv")
    OutputFile.writeString(f, "old\n")
    intercept[IllegalStateException](OutputFile.writeText(f) { w =>
      w.write("partial")
      throw new IllegalStateException("stop")
    })
    assert(read(f) == "old\n" && listing(dir) == Seq("t.csv"))
  }
}
