// An sbt project of its own that uses the reducer-load generator as a library, by its published
// coordinates: in the repository root, `./sbt publishLocal` first; then here, `../sbt test`.
// The same Scala, Chisel and chiseltest versions as the library (the Chisel plugin is per exact Scala version).
ThisBuild / scalaVersion := "2.13.15"

val chiselVersion = "6.7.0"

lazy val root = (project in file("."))
  .settings(
    name := "reducer-load-example",
    libraryDependencies ++= Seq(
      "io.reducerload" %% "reducer-load" % "0.1.0",
      "org.chipsalliance" %% "chisel" % chiselVersion,
      "edu.berkeley.cs" %% "chiseltest" % "6.0.0" % Test,
      "org.scalatest" %% "scalatest" % "3.2.19" % Test
    ),
    addCompilerPlugin(("org.chipsalliance" % "chisel-plugin" % chiselVersion).cross(CrossVersion.full)),
    scalacOptions ++= Seq("-language:reflectiveCalls", "-deprecation", "-feature", "-Xfatal-warnings"),
    Test / fork := true,
    Test / javaOptions ++= Seq("-Xss8m", "-Xmx2g")
  )
