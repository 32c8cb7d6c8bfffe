// Formatting is checked in CI (`scalafmtCheckAll`); `./sbt scalafmtAll` formats the sources.
addSbtPlugin("org.scalameta" % "sbt-scalafmt" % "2.5.2")
