package reducerload.robot

import reducerload.trace.InputError

/** Placeholder until the URDF reader lands. */
object Urdf {
  def read(path: java.nio.file.Path, tip: Option[String]): SerialChain = throw new InputError(s"$path: URDF reading is not available yet")
}
