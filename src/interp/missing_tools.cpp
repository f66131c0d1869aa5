// A tool the tool table lacks under every dialect but LinuxCNC's: a zero-length tool, with a
// warning (posts name the tools of the machine they were written for).
#include "interp/dialect.hpp"

#include <fmt/format.h>

#include <cmath>

namespace gm {

void DialectRules::missing_tools(const grammar::Block& block, const ToolTable& tools,
                                 const std::string& text, std::vector<Diagnostic>& diags,
                                 std::vector<ToolEntry>& add) const {
  if (dialect_ == Dialect::LinuxCNC) return;
  bool named = false, comp = false;  // D names a tool on G41/G42 only (G41.1 D: a diameter)
  for (const grammar::Word& w : block.words) {
    switch (w.letter) {
      case 'T':
      case 'H':
      case 'D':
        named = true;
        break;
      case 'G':
        comp = comp || w.value == 41.0 || w.value == 42.0;
        break;
      default:
        break;
    }
  }
  if (!named) return;
  for (const grammar::Word& w : block.words) {
    if (w.letter != 'T' && w.letter != 'H' && !(w.letter == 'D' && comp)) continue;
    const double n = std::round(w.value);
    if (std::fabs(w.value - n) > 1e-6 || n < 1 || n > 1e6) continue;  // the interpreter's errors
    const int tool = static_cast<int>(n);
    if (tools.find(tool) != nullptr) continue;
    bool added = false;
    for (const ToolEntry& e : add) added = added || e.number == tool;
    if (added) continue;
    ToolEntry e;
    e.number = tool;
    e.pocket = tool;
    e.comment = "zero-length tool: not in the tool table";
    add.push_back(e);
    diags.push_back(Diagnostic{Severity::Warning, 0, w.loc,
                               fmt::format("tool {} is not in the tool table ({}): a tool of "
                                           "length and diameter 0 (--dialect {})",
                                           tool, tools.source, dialect_name(dialect_)),
                               echoed_line(text)});
  }
}

}  // namespace gm
