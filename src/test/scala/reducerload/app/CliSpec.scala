package reducerload.app

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.load.{LoadModel, LoadParams}
import reducerload.trace.InputError

import java.nio.file.Files

class CliSpec extends AnyFlatSpec {
  behavior of "the command line"

  private def params(args: String*) = Cli.parse("emit", args, Emit.options).params

  it should "start from the default preset and apply flag overrides" in {
    assert(params() == LoadParams.default)
    assert(params("--preset", "paper") == LoadParams.paper)
    val p = params("--m3", "12", "--model", "paper", "--max-velocity", "1,2,3", "--cordic.iterations=20")
    assert(p.robot.m3 == 12 && p.model == LoadModel.PaperEq6 && p.robot.maxVelocity == Seq(1.0, 2.0, 3.0) && p.cordic.iterations == 20)
  }

  it should "refuse bad flags with one line naming the flag" in {
    def refused(args: Seq[String], word: String): Unit = {
      val e = intercept[InputError](params(args: _*))
      assert(e.getMessage.contains(word) && !e.getMessage.contains("\n"), e.getMessage)
    }
    refused(Seq("--frobnicate", "1"), "--frobnicate")
    refused(Seq("--m3"), "--m3 needs a value")
    refused(Seq("--m3", "heavy"), "robot.m3")
    refused(Seq("--m3", "NaN"), "robot.m3")
    refused(Seq("--preset", "fastest-ever"), "fastest-ever")
    refused(Seq("--preset", "paper", "--config", "x.conf"), "exclusive")
    refused(Seq("--config", "/nonexistent/x.conf"), "/nonexistent/x.conf")
    refused(Seq("--l2", "-0.3"), "l2")
  }

  it should "name the file when a configuration file is not HOCON" in {
    val f = Files.createTempFile("bad", ".conf")
    Files.write(f, Array[Byte](0, 1, 2, '{'.toByte, '{'.toByte))
    val e = intercept[InputError](params("--config", f.toString))
    assert(e.getMessage.contains(f.toString), e.getMessage)
    Files.delete(f)
  }

  it should "document every setting with its unit and default in --help" in {
    val h = Main.help
    reducerload.config.Settings.all.foreach { s =>
      assert(h.contains("--" + s.key), s"--help lacks ${s.key}")
      assert(h.contains(s"(default ${s.render(LoadParams.default)})"))
    }
  }
}
