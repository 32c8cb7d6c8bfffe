package reducerload.config

import org.scalatest.flatspec.AnyFlatSpec

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Paths}

class SettingsDocSpec extends AnyFlatSpec {
  behavior of "docs/configuration.md"

  it should "be what run configuration-doc generates from the settings' declarations" in {
    val committed =
      new String(Files.readAllBytes(Paths.get("docs", "configuration.md")), StandardCharsets.UTF_8)
    assert(
      committed == SettingsDoc.markdown,
      "docs/configuration.md is stale: ./sbt --error \"run configuration-doc\" > docs/configuration.md"
    )
  }

  it should "hold no Scala placeholder left uninterpolated in a setting's help (a string without s\"\")" in {
    val raw = Settings.all.filter(_.help.contains("${"))
    assert(raw.isEmpty, s"help with a literal $${...}: ${raw.map(_.key).mkString(", ")}")
  }
}
