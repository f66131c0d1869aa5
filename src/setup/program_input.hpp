// A program opened for reading twice (checked, then run), stdin spooled to a file first.
#pragma once

#include "interp/program.hpp"

#include <fstream>
#include <string>
#include <vector>

namespace gm::setup {

/// A program opened for reading twice (validate, then run). `-` spools stdin to a temporary
/// file first, so the same bytes are checked and run.
class ProgramInput {
 public:
  explicit ProgramInput(const std::string& path);  ///< throws gm::InputError naming the path
  std::istream& rewind();                          ///< the stream, at the start
  const std::string& name() const { return name_; }

 private:
  static constexpr std::size_t kBufferBytes = std::size_t{1} << 20;
  std::string name_;
  std::vector<char> buffer_;  ///< the stream's buffer (set before open); declared before file_
  std::ifstream file_;
  std::string spool_path_;
};

/// Validates the program; prints its diagnostics to stderr. Returns true when it has no error.
bool validate_program(ProgramInput& program, const InterpreterOptions& opts);

}  // namespace gm::setup
