// Haas's local subprogram call (--dialect haas) in OwordFlow: M97 P n L k runs the blocks from
// N n of the same program to M99, k times, over the same call stack and sequence search as M98
// and GOTO.
#include "interp/oword_flow.hpp"

#include <fmt/format.h>

#include <cmath>

namespace gm {

bool OwordFlow::m97(const grammar::Block& b, const LinePos& pos, InterpError& err) {
  const grammar::Word* m97 = nullptr;
  const grammar::Word* p = nullptr;
  const grammar::Word* l = nullptr;
  for (const grammar::Word& w : b.words) {
    if (w.letter == 'M' && w.value == 97.0 && m97 == nullptr) {
      m97 = &w;
    } else if (w.letter == 'P' && p == nullptr) {
      p = &w;
    } else if (w.letter == 'L' && l == nullptr) {
      l = &w;
    } else if (w.letter != 'N') {
      return fail(
          err, ErrorCode::SubprogramMisused, w.loc,
          fmt::format("M97 takes P (the sequence number) and L (repeats) only, not {}", w.letter));
    }
  }
  const SourceLoc loc = m97 != nullptr ? m97->loc : SourceLoc{pos.line, 1};
  if (p == nullptr)
    return fail(err, ErrorCode::SubprogramMisused, loc,
                "M97 needs P, the sequence number (N) of the local subprogram");
  const double n = std::round(p->value);
  if (std::fabs(p->value - n) > 1e-4 || n < 1 || n > 99999)
    return fail(err, ErrorCode::SubprogramMisused, p->loc,
                fmt::format("M97 P{}: the target is a sequence number 1-99999", p->value));
  // L repeats as M98's (LinuxCNC's m98_loop_counter): the return comes back to this line.
  if (!count_repeat(l)) return true;
  pending_args_.clear();
  pending_return_ = pos;
  pending_fanuc_ = true;  // ends with M99; #1-#33 shared with the caller
  pending_macro_ = false;
  FlowJump none;
  if (!enter_sub(fmt::format("N{}", static_cast<long>(n)), pos, loc, none, false, err))
    return false;
  // The body is found as GOTO finds its target: forward to the program's end, then from its
  // start.
  skip_ = SkipState{};
  skip_.mode = Skip::FindSequence;
  skip_.sequence = static_cast<long>(n);
  skip_.from = pos;
  skip_.started = loc;
  skip_.started_file = skip_.file = pos.file;
  skip_.shown = fmt::format("M97 P{}", skip_.sequence);
  return true;
}

}  // namespace gm
