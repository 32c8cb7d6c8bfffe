package reducerload.architecture

import com.tngtech.archunit.core.importer.ClassFileImporter
import com.tngtech.archunit.library.dependencies.SlicesRuleDefinition.slices
import org.scalatest.flatspec.AnyFlatSpec

/**
 * No package depends, directly or through others, on itself: the layers read bottom-up (util, fixedpoint,
 * pipeline, cordic, robot, dynamics, graph, load, config, arm, monitor, compiler, sim, app, api), so a reader
 * can learn each from the ones below it. Checked on the compiled main classes, not the sources.
 */
class ArchitectureSpec extends AnyFlatSpec {
  behavior of "the main packages"

  it should "be free of cycles" in {
    // The main classes' directory (sbt's test classes sit elsewhere, and test helpers may cross layers).
    val main = java.nio.file.Paths
      .get(reducerload.app.Main.getClass.getProtectionDomain.getCodeSource.getLocation.toURI)
    val classes = new ClassFileImporter().importPath(main)
    assert(
      classes.size > 100,
      s"only ${classes.size} classes found: the import no longer sees the main classes"
    )
    // Top-level packages with their subpackages (sim.rtl, sim.model, ... are one slice), then every package
    // on its own, so a cycle between two subpackages fails too.
    slices().matching("reducerload.(*)..").should().beFreeOfCycles().check(classes)
    slices().matching("reducerload.(**)").should().beFreeOfCycles().check(classes)
  }
}
