// Reducer-load calculator generator: Chisel 6 + chiseltest, pinned versions.
// The Chisel compiler plugin is published per exact Scala version: keep 2.13.15.
ThisBuild / scalaVersion := "2.13.15"
ThisBuild / version := "0.1.0"
ThisBuild / organization := "io.reducerload"

val chiselVersion = "6.7.0"

lazy val root = (project in file("."))
  .settings(
    name := "reducer-load",
    libraryDependencies ++= Seq(
      "org.chipsalliance" %% "chisel" % chiselVersion,
      // Compile scope: `run simulate` drives the generated RTL on Verilator through it.
      "edu.berkeley.cs" %% "chiseltest" % "6.0.0",
      "org.scalatest" %% "scalatest" % "3.2.19" % Test,
      // Only trace/DecimalBenchmark: a maintained CSV reader measured against CsvRecordReader.
      "org.apache.commons" % "commons-csv" % "1.12.0" % Test,
      // graph/LatencySearch: the shortest registers-storage schedule (CP-SAT), and
      // graph/SchedulerComparison: the refinement measured against it.
      "com.google.ortools" % "ortools-java" % "9.14.6206",
      // The package-cycle test (ArchitectureSpec) reads the compiled classes' dependencies.
      "com.tngtech.archunit" % "archunit" % "1.3.0" % Test,
      "com.typesafe" % "config" % "1.4.3",
      // Decimal text to double, correctly rounded (trace/CsvRecordReader.scala).
      "ch.randelshofer" % "fastdoubleparser" % "2.0.1",
      // URDF robot descriptions (robot/Urdf.scala). 2.3.0 is the newest release built on a
      // scala-library no newer than our 2.13.15 (2.4.0 needs 2.13.16, which sbt refuses).
      "org.scala-lang.modules" %% "scala-xml" % "2.3.0"
    ),
    addCompilerPlugin(("org.chipsalliance" % "chisel-plugin" % chiselVersion).cross(CrossVersion.full)),
    scalacOptions ++= Seq(
      "-language:reflectiveCalls",
      "-deprecation",
      "-feature",
      "-unchecked",
      "-Xcheckinit",
      "-Xfatal-warnings",
      "-Ymacro-annotations"
    ),
    // Suites run side by side in the one forked JVM, as many as there are cores: most of a suite's time
    // is one thread (a schedule's refinement, an elaboration, a simulation), so on CI's two cores two
    // suites take about the wall time of one. Harness builds of one design are safe side by side
    // (VerilatorHarness renames a finished build into place).
    Test / fork := true,
    Test / testForkedParallel := true,
    Test / javaOptions ++= Seq("-Xss8m", "-Xmx6g"),
    // Verilator's makefiles build the evaluation code at -Os, which takes minutes for a 6-axis arm's
    // datapath; the tests run a few thousand cycles, and -O1 builds it about ten times faster.
    Test / envVars += "MAKEFLAGS" -> "OPT_FAST=-O1",
    // Tests name repository files by relative paths: the caller's directory (./sbt exports it) is not theirs.
    Test / envVars += "REDUCERLOAD_CWD" -> baseDirectory.value.getAbsolutePath,
    run / fork := true,
    run / connectInput := true,
    run / javaOptions ++= Seq("-Xss8m", "-Xmx4g"),
    // The user's working directory, so relative --input/--output paths mean what they say.
    run / baseDirectory := file("."),
    Compile / mainClass := Some("reducerload.app.Main"),
    Test / testOptions += Tests.Argument(TestFrameworks.ScalaTest, "-oD"),
    // `publishLocal` (docs/library.md): the classes and their sources (whose Scaladoc IDEs show), no Scaladoc
    // jar: generating it type-checks every source again (minutes in CI) and its link checks are not ours.
    Compile / packageDoc / publishArtifact := false
  )

// The robots the library API builds by name (reducerload.api.Robot.Bundled), with their licences and notes:
// in the jar, so a library user finds them from any directory.
Compile / resourceGenerators += Def.task {
  val robots = (Compile / resourceManaged).value / "reducerload" / "robots"
  val files = (baseDirectory.value / "golden" / "robots").listFiles().toSeq.filter(_.isFile)
  files.map { f =>
    val to = robots / f.getName
    IO.copyFile(f, to)
    to
  }
}.taskValue

// The generator's version for the register map's identification block (regmap/ReducerLoadRegisters.scala):
// written once here, read as a resource.
Compile / resourceGenerators += Def.task {
  val file = (Compile / resourceManaged).value / "reducerload" / "version.txt"
  IO.write(file, version.value + "\n")
  Seq(file)
}.taskValue
