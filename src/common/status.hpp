// Exit codes of the command line and the exception types that map onto them.
#pragma once

#include <stdexcept>
#include <string>

namespace gm {

/// Process exit codes (documented in the README).
enum class ExitCode : int {
  Ok = 0,            ///< success
  InputError = 1,    ///< the program, machine file, schedule or trace is wrong (located message)
  UsageError = 2,    ///< bad command line
  InternalError = 3  ///< a bug or an environment failure (disk full, ...)
};

/// Bad configuration or input that is not G-code (machine file, flags, schedule):
/// the message names the value, the key or axis, and where it came from.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace gm
