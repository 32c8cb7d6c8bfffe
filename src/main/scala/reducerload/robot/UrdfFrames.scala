package reducerload.robot

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path}

/** Frames of a URDF robot's links, as the chain that [[Urdf.read]] builds sees them. */
object UrdfFrames {

  /**
   * The pose of link `frame` (None: the tip) in the frame of the last moving joint of the chain to `tip`
   * (None: the only leaf): that link must be fixed to that joint (the tip itself, a flange or tool frame, any
   * link reached from the joint through fixed joints only). `key` names the setting in a refusal.
   */
  def fixedToLast(
      path: Path,
      tip: Option[String],
      allowMassless: Boolean,
      frame: Option[String],
      key: String
  ): Transform = {
    val source = path.toString
    val chain = Urdf.read(path, tip, allowMassless) // every check of the file and the tip, once
    val robot = new UrdfParser(source).robot(new String(Files.readAllBytes(path), StandardCharsets.UTF_8))
    val parentJoint = robot.joints.map(j => j.child -> j).toMap
    // The chain was read, so without a tip there is exactly one leaf.
    val link =
      frame.orElse(tip).getOrElse(robot.links.map(_.name).filterNot(robot.joints.map(_.parent).toSet).head)
    if (!robot.links.exists(_.name == link))
      throw Urdf.error(source, key, s"unknown link '$link'")
    val joints = List.unfold(link)(l => parentJoint.get(l).map(j => (j, j.parent))).reverse
    val lastMoving = chain.joints.last.name
    val after = joints.dropWhile(_.name != lastMoving)
    if (after.isEmpty || after.tail.exists(_.motion.isDefined))
      throw Urdf.error(
        source,
        key,
        s"link '$link' is not fixed to the last moving joint '$lastMoving' of the chain"
      )
    after.tail.foldLeft(Transform.identity)((pose, j) => pose.compose(j.origin))
  }
}
