// Mach3's codes that LinuxCNC spells differently or lacks (--dialect mach3): G31, the straight
// probe, is G38.2; M47, repeat from the first line, ends the program.
#include "interp/block_edit.hpp"
#include "interp/dialect.hpp"

namespace gm {

void DialectRules::mach3_codes(grammar::Block& block, const std::string& text,
                               std::vector<Diagnostic>& diags) {
  if (const std::size_t i = block_edit::find_code(block, 'G', 310); i != block_edit::kNone)
    block.words[i].value = 38.2;  // straight probe: stops at contact, an error without one
  if (const std::size_t i = block_edit::find_code(block, 'M', 470); i != block_edit::kNone) {
    if (!m47_warned_) {
      m47_warned_ = true;
      diags.push_back(Diagnostic{Severity::Warning, 0, block.words[i].loc,
                                 "M47 (repeat the program from its first line) ends the program "
                                 "here as M2: the repeats would not end (--dialect mach3)",
                                 echoed_line(text)});
    }
    block.words[i].value = 2.0;
  }
}

}  // namespace gm
