// A located diagnostic (file:line:col) and its rendering with the source line and a caret.
#pragma once

#include <string>
#include <string_view>

namespace gm {

/// A position in a source file; line and column are 1-based, column counts bytes.
struct SourceLoc {
  int line = 0;
  int column = 0;
};

enum class Severity { Error, Warning, Note };

/// One message about an input file. `code` is a catalogue entry (see common/error_codes.hpp)
/// for G-code diagnostics, or 0 for others.
struct Diagnostic {
  Severity severity = Severity::Error;
  int code = 0;
  SourceLoc loc;
  std::string message;
  std::string source_line;  ///< the text of the line, for the caret display (may be empty)
  std::string file{};       ///< the file it is in when not the one being read (a subroutine file)
};

/// Renders `file:line:col: error: message`, then the source line and a caret under the column;
/// `d.file`, when set, is the file named instead of `file`.
std::string format_diagnostic(std::string_view file, const Diagnostic& d);

}  // namespace gm
