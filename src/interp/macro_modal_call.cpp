// Fanuc's modal macro call G66/G67: the G66 line becomes the G65 call made after each move.
#include "interp/macro_modal_call.hpp"

#include "common/error_codes.hpp"
#include "interp/block_edit.hpp"

#include <fmt/format.h>

namespace gm {

namespace be = block_edit;

bool ModalMacroCall::take(grammar::Block& block, int call_depth, InterpError& err) {
  bool any = false;  // (most blocks have neither: looked at once)
  for (const grammar::Word& w : block.words)
    any = any || (w.letter == 'G' && (w.value == 66.0 || w.value == 67.0));
  if (!any) return true;
  if (const std::size_t i = be::find_code(block, 'G', 670); i != be::kNone) {
    on_ = false;
    be::erase(block, i);
  }
  const std::size_t g66 = be::find_code(block, 'G', 660);
  if (g66 == be::kNone) return true;
  const SourceLoc loc = block.words[g66].loc;
  grammar::Block call;
  call.line = block.line;
  call.oword.kind = grammar::OKind::G65;
  call.oword.loc = loc;
  call.words.push_back(grammar::Word{'G', 65.0, loc});
  for (std::size_t i = 0; i < block.words.size(); ++i) {
    const grammar::Word& w = block.words[i];
    if (i == g66 || w.letter == 'N') continue;
    if (w.letter == 'G' || w.letter == 'M')
      return fail(err, ErrorCode::SubprogramMisused, w.loc,
                  fmt::format("{}{} on a G66 line: a modal macro call takes P (program) and the "
                              "arguments only",
                              w.letter, w.value));
    if (w.letter == 'L' && w.value != 1.0)
      return fail(err, ErrorCode::NotInDialect, w.loc,
                  "G66 L (repeats of each call) is not read: one call after each move");
    if (w.letter != 'L') call.words.push_back(w);
  }
  if (be::find(call, 'P') == be::kNone)
    return fail(err, ErrorCode::SubprogramMisused, loc,
                "G66 needs P, the number of the macro program (O1234 ... M99) to call");
  call_ = std::move(call);
  on_ = true;
  depth_ = call_depth;
  block.words.clear();  // the G66 line itself moves nothing
  return true;
}

const grammar::Block* ModalMacroCall::after(const grammar::Block& block, int call_depth) const {
  if (!on_ || call_depth != depth_) return nullptr;  // (not in the blocks of the macro itself)
  for (const grammar::Word& w : block.words) switch (w.letter) {
      case 'X':
      case 'Y':
      case 'Z':
      case 'A':
      case 'B':
      case 'C':
      case 'U':
      case 'V':
      case 'W':
        return &call_;
      default:
        break;
    }
  return nullptr;
}

}  // namespace gm
