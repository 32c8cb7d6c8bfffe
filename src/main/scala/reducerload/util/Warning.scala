package reducerload.util

/**
 * Something a user should know about an input that is still accepted (a link taken as massless, a design
 * larger than the device it targets): printed as one line `warning: <where>: <message>` on standard error and
 * listed in the report.
 *
 * @param where
 *   the input it is about (a URDF file and element, a setting)
 */
final case class Warning(where: String, message: String) {
  override def toString: String = s"warning: $where: $message"
}
