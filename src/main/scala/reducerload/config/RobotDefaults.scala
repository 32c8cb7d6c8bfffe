package reducerload.config

/**
 * The defaults a robot given on the command line (`--robot FILE`) brings instead of the `default` preset's:
 * the `arm` preset, and the values below unless their flags are given. Help and the settings reference show
 * them beside each default, so that a URDF user does not read planar3's velocity limits as theirs.
 */
object RobotDefaults {

  /** The preset `--robot` starts from unless --preset is given. */
  val preset: String = "arm"

  /** Settings `--robot FILE` sets (a URDF's, not planar3's), unless given: key and value. */
  val implied: Seq[(String, String)] =
    Seq("model" -> "rnea", "robot.max-velocity" -> "urdf", "robot.tip" -> "")

  /** A URDF gives no acceleration limits: `--robot FILE` needs this setting. */
  val required: String = "robot.max-acceleration"

  /** What `s` is for a URDF given by `--robot`, when that differs from the `default` preset's value. */
  def note(s: Setting[_]): Option[String] = {
    val withRobot =
      if (s.key == required) Some("required")
      else if (s.key == Settings.robotSource.key) None
      else
        implied
          .collectFirst { case (s.key, v) => if (v.isEmpty) "\"\"" else v }
          .orElse(Some(s.render(LoadParams.allPresets(preset))))
    withRobot.filter(_ != s.render(LoadParams.default))
  }
}
