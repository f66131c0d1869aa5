// Rendering of located diagnostics in the compiler style users know (file:line:col + caret).
#include "common/diagnostic.hpp"

#include <fmt/format.h>

namespace gm {

std::string format_diagnostic(std::string_view file, const Diagnostic& d) {
  const char* kind = d.severity == Severity::Error     ? "error"
                     : d.severity == Severity::Warning ? "warning"
                                                       : "note";
  std::string out =
      fmt::format("{}:{}:{}: {}: {}\n", d.file.empty() ? file : std::string_view(d.file),
                  d.loc.line, d.loc.column, kind, d.message);
  if (!d.source_line.empty()) {
    std::string line = d.source_line;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    out += fmt::format("  {}\n", line);
    // Keep tabs under tabs so the caret lines up whatever the tab width.
    std::string pad;
    for (int i = 0; i + 1 < d.loc.column && i < static_cast<int>(line.size()); ++i)
      pad += line[static_cast<std::size_t>(i)] == '\t' ? '\t' : ' ';
    out += fmt::format("  {}^\n", pad);
  }
  return out;
}

}  // namespace gm
