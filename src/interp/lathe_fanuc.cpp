// Fanuc/Haas lathe words rewritten into the interpreter's: U/W, T0101, G50, G96's clamp, G98/G99,
// and the first blocks of the two-block cycles (their second blocks: lathe_fanuc_cycles.cpp).
#include "interp/lathe_fanuc.hpp"

#include "interp/frame.hpp"
#include "motion/geometry.hpp"

#include <fmt/format.h>

#include <cmath>

namespace gm {

namespace {

constexpr std::size_t kNone = static_cast<std::size_t>(-1);
constexpr std::size_t kMaxSeenSequences = std::size_t{1} << 16;

// The G word `number10` (G71 = 710) in `b`, or kNone.
std::size_t find_g(const grammar::Block& b, int number10) {
  for (std::size_t i = 0; i < b.words.size(); ++i) {
    const grammar::Word& w = b.words[i];
    if (w.letter == 'G' && std::fabs(w.value * 10.0 - number10) < 1e-6) return i;
  }
  return kNone;
}

std::size_t find_letter(const grammar::Block& b, char c) {
  for (std::size_t i = 0; i < b.words.size(); ++i)
    if (b.words[i].letter == c) return i;
  return kNone;
}

bool has_m(const grammar::Block& b, double m) {
  for (const grammar::Word& w : b.words)
    if (w.letter == 'M' && w.value == m) return true;
  return false;
}

bool has_tool_length_code(const grammar::Block& b) {
  for (const grammar::Word& w : b.words)
    if (w.letter == 'G' && (std::fabs(w.value - 49.0) < 1e-9 || std::fabs(w.value - 43.0) < 1e-9 ||
                            std::fabs(w.value - 43.1) < 1e-9 || std::fabs(w.value - 43.2) < 1e-9))
      return true;
  return false;
}

bool located(InterpError& err, ErrorCode code, SourceLoc loc, std::string msg) {
  return fail(err, code, loc, std::move(msg));
}

}  // namespace

void FanucLathe::start_block(grammar::Block& block) {
  block.words.push_back(grammar::Word{'G', 7.0, SourceLoc{1, 1}});
  block.words.push_back(grammar::Word{'G', 18.0, SourceLoc{1, 1}});
  // A Fanuc or Haas lathe powers on in G99 (feed per revolution): posts leave it out.
  block.words.push_back(grammar::Word{'G', 95.0, SourceLoc{1, 1}});
}

bool FanucLathe::rewrite(grammar::Block& b, const ModalState& s, Outcome& outcome,
                         InterpError& err) {
  outcome = Outcome::Run;
  for (const grammar::Word& w : b.words)  // (the evaluator refuses these; kept out of cycles)
    if (!std::isfinite(w.value)) return located(err, ErrorCode::NotANumber, w.loc, "not a number");
  for (const int code : {700, 710, 720, 730})
    if (find_g(b, code) != kNone) return profile_cycle(b, code / 10, s, outcome, err);
  if (find_g(b, 760) != kNone) return thread_cycle(b, s, outcome, err);
  for (const int code : {740, 750})
    if (find_g(b, code) != kNone) return peck_cycle(b, code / 10, s, outcome, err);
  // G-code system A has no G90/G91 absolute/incremental modes: X, Z are absolute and U, W
  // incremental; G90 is the outer/inner diameter cutting cycle.
  if (const std::size_t i = find_g(b, 910); i != kNone)
    return located(err, ErrorCode::NotInDialect, b.words[i].loc,
                   "G91 is not a code of a Fanuc lathe (G-code system A): U and W are the "
                   "incremental words of X and Z, and G90 is the diameter cutting cycle");
  // G90, G92, G94: the single cycles (modal in group 1, repeated by blocks of X/Z words).
  bool single = false;
  if (!single_cycle(b, s, outcome, single, err)) return false;
  if (single) return true;
  // G32: thread cutting, F the lead (LinuxCNC's G33 K).
  if (const std::size_t g32 = find_g(b, 320); g32 != kNone) {
    b.words[g32].value = 33.0;
    if (const std::size_t f = find_letter(b, 'F'); f != kNone) b.words[f].letter = 'K';
  }
  // G50: S the spindle clamp (the maximum spindle speed), X Z a coordinate setting as G92.
  if (const std::size_t g50 = find_g(b, 500); g50 != kNone) {
    if (const std::size_t si = find_letter(b, 'S'); si != kNone) {
      if (!(b.words[si].value >= 0.0))
        return located(err, ErrorCode::NegativeValue, b.words[si].loc,
                       fmt::format("G50 S{:g}: the spindle clamp is negative", b.words[si].value));
      clamp_rpm_ = b.words[si].value;
      b.words.erase(b.words.begin() + static_cast<std::ptrdiff_t>(si));
      if (s.css) {  // G96 in force: its cap follows now
        b.words.push_back(grammar::Word{'G', 96.0, b.words[g50].loc});
        b.words.push_back(grammar::Word{'S', s.spindle_rpm, b.words[g50].loc});
        b.words.push_back(grammar::Word{'D', clamp_rpm_, b.words[g50].loc});
      }
    }
    const bool coords = find_letter(b, 'X') != kNone || find_letter(b, 'Z') != kNone ||
                        find_letter(b, 'U') != kNone || find_letter(b, 'W') != kNone;
    if (coords)
      b.words[g50].value = 92.0;
    else
      b.words.erase(b.words.begin() + static_cast<std::ptrdiff_t>(g50));
  }
  // G96 S: surface speed, capped by G50 S.
  if (const std::size_t g96 = find_g(b, 960);
      g96 != kNone && clamp_rpm_ > 0.0 && find_letter(b, 'D') == kNone)
    b.words.push_back(grammar::Word{'D', clamp_rpm_, b.words[g96].loc});
  // G98/G99 on a lathe (G-code system A): feed per minute / per revolution.
  for (grammar::Word& w : b.words)
    if (w.letter == 'G' && (w.value == 98.0 || w.value == 99.0))
      w.value = w.value == 98.0 ? 94.0 : 95.0;
  if (const std::size_t t = find_letter(b, 'T'); t != kNone && !rewrite_tool(b, t, err))
    return false;
  if (!rewrite_incremental(b, s, err)) return false;
  // Only what the interpreter should see is left: a bare G50 S ran already.
  bool sequence_only = true;
  for (const grammar::Word& w : b.words)
    if (w.letter != 'N') sequence_only = false;
  if (sequence_only && b.message_count == 0) outcome = Outcome::Recorded;
  return true;
}

// T0101: tool 01 with offset 01 (the upper digits the tool, the lower two the offset); T0100
// cancels the offset. As LinuxCNC words: T1 M61 Q1 G43 H1 (G49 for offset 0): the turret
// indexes without stopping the spindle (M6 would stop it).
bool FanucLathe::rewrite_tool(grammar::Block& b, std::size_t t, InterpError& err) const {
  const grammar::Word tw = b.words[t];
  const double v = tw.value;
  if (!(v >= 0.0) || std::fabs(v - std::round(v)) > 1e-9 || v > 999999.0)
    return located(err, ErrorCode::BadCodeNumber, tw.loc,
                   fmt::format("T{:g}: a lathe T word is the tool and its offset, T0101", v));
  const long code = std::lround(v);
  const long tool = code / 100, offset = code % 100;
  b.words[t].value = static_cast<double>(tool);
  if (!has_m(b, 6.0) && !has_m(b, 61.0)) {
    b.words.push_back(grammar::Word{'M', 61.0, tw.loc});
    b.words.push_back(grammar::Word{'Q', static_cast<double>(tool), tw.loc});
  }
  if (!has_tool_length_code(b)) {
    if (offset == 0) {
      b.words.push_back(grammar::Word{'G', 49.0, tw.loc});
    } else {
      b.words.push_back(grammar::Word{'G', 43.0, tw.loc});
      b.words.push_back(grammar::Word{'H', static_cast<double>(offset), tw.loc});
    }
  }
  return true;
}

// U and W: X (a diameter) and Z incremental in a block of absolute words; with X (Z) in the same
// block an error.
bool FanucLathe::rewrite_incremental(grammar::Block& b, const ModalState& s,
                                     InterpError& err) const {
  struct Pair {
    char inc, abs;
    int axis;
  };
  for (const Pair p : {Pair{'U', 'X', 0}, Pair{'W', 'Z', 2}}) {
    const std::size_t i = find_letter(b, p.inc);
    if (i == kNone) continue;
    if (const std::size_t a = find_letter(b, p.abs); a != kNone)
      return located(err, ErrorCode::DuplicateWord, b.words[i].loc,
                     fmt::format("{} and {} in one block: on a Fanuc lathe {} is {}'s incremental "
                                 "word (the {} axis)",
                                 p.inc, p.abs, p.inc, p.abs, p.abs));
    grammar::Word& w = b.words[i];
    w.letter = p.abs;
    if (s.incremental) continue;  // G91: X is incremental already
    // From the programmed point (under G41/G42 the compensation's, as LinuxCNC's find_ends).
    Pos9 point = s.position_mm;
    if (s.comp.on() && !s.comp.first_move) {
      const auto axes = plane_axes(s.plane);
      point[axes.a] = s.comp.prog_a;
      point[axes.b] = s.comp.prog_b;
    }
    const double here = Frame(s).to_program(point)[p.axis] / s.mm_per_unit();
    w.value += p.axis == 0 && s.lathe_diameter ? 2.0 * here : here;
  }
  return true;
}

void FanucLathe::note_sequence(long n, const Seen& at) {
  if (n < 0 || (seen_.size() >= kMaxSeenSequences && seen_.find(n) == seen_.end())) return;
  seen_[n] = at;
}

const FanucLathe::Seen* FanucLathe::seen(long n) const {
  const auto it = seen_.find(n);
  return it == seen_.end() ? nullptr : &it->second;
}

}  // namespace gm
