package reducerload.util

/**
 * A user's mistake in an input (a flag, a configuration, a URDF, a CSV): one line that names the input and
 * what is wrong. `Main` prints it as `error: ...` and exits with status 2, no stack trace.
 */
final class InputError(message: String) extends Exception(message)
