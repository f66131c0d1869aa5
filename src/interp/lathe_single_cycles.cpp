// G-code system A's single cycles on a Fanuc/Haas lathe: G90 (outer/inner diameter cutting), G92
// (threading) and G94 (end face cutting), modal in group 1 and repeated by blocks of X/Z words.
#include "interp/frame.hpp"
#include "interp/lathe_fanuc.hpp"

#include <fmt/format.h>

#include <cmath>
#include <string_view>

namespace gm {

namespace {

constexpr std::size_t kNoWord = static_cast<std::size_t>(-1);
constexpr double kSameTol = 1e-9;
using Kind = LatheMove::Kind;

bool is_g(const grammar::Word& w, double number) {
  return w.letter == 'G' && std::fabs(w.value - number) < 1e-6;
}

bool is_axis(char c) {
  return c == 'X' || c == 'Z' || c == 'U' || c == 'W';
}

// Group-1 codes that cancel a single cycle: the motions (G32 is the lathe's thread cutting).
bool is_motion(const grammar::Word& w) {
  return is_g(w, 0) || is_g(w, 1) || is_g(w, 2) || is_g(w, 3) || is_g(w, 32) || is_g(w, 33);
}

// Group-0 codes whose X/Z words are their own (dwell, data setting, reference points, coordinate
// setting): such a block does not repeat the cycle in force.
bool takes_own_axes(const grammar::Word& w) {
  for (const double n : {4.0, 10.0, 27.0, 28.0, 29.0, 30.0, 50.0, 52.0, 53.0})
    if (is_g(w, n)) return true;
  return false;
}

const char* cycle_title(int code) {
  return code == 90   ? "outer/inner diameter cutting"
         : code == 92 ? "threading"
                      : "end face cutting";
}

}  // namespace

void FanucLathe::single_cycle_moves(const SingleInput& in, std::vector<LatheMove>& out) {
  auto add = [&](Kind k, double z, double x, double f) {
    LatheMove m;
    m.kind = k;
    m.z = z;
    m.x = x;
    m.f = k == Kind::Rapid ? -1.0 : f;
    out.push_back(m);
  };
  if (in.code == 94) {
    add(Kind::Rapid, in.ze + in.taper, in.x0, -1.0);  // 1 (rapid): in Z to the cut's start
    add(Kind::Feed, in.ze, in.xe, in.f);              // 2 (feed): across the face
    add(Kind::Feed, in.z0, in.xe, in.f);              // 3 (feed): out in Z to the start's Z
    add(Kind::Rapid, in.z0, in.x0, -1.0);             // 4 (rapid): back in X
    return;
  }
  const bool thread = in.code == 92;
  add(Kind::Rapid, in.z0, in.xe + in.taper, -1.0);              // 1: in X to the cut's start
  add(thread ? Kind::Thread : Kind::Feed, in.ze, in.xe, in.f);  // 2: along Z to the end
  add(thread ? Kind::Rapid : Kind::Feed, in.ze, in.x0, in.f);   // 3: out in X
  add(Kind::Rapid, in.z0, in.x0, -1.0);                         // 4: back in Z
}

bool FanucLathe::single_cycle(grammar::Block& b, const ModalState& s, Outcome& outcome,
                              bool& handled, InterpError& err) {
  handled = false;
  std::size_t cyc = kNoWord, motion = kNoWord;
  bool own_axes = false, axes = false;
  for (std::size_t i = 0; i < b.words.size(); ++i) {
    const grammar::Word& w = b.words[i];
    axes = axes || is_axis(w.letter);
    if (w.letter != 'G') continue;
    if (is_g(w, 90) || is_g(w, 92) || is_g(w, 94) || is_motion(w)) {
      const std::size_t other = cyc != kNoWord ? cyc : motion;
      if (other != kNoWord)
        return fail(err, ErrorCode::ModalGroupViolation, w.loc,
                    fmt::format("G{:g} and G{:g} in one block: on a Fanuc lathe both are group 1 "
                                "codes (G90/G92/G94 are the single cycles of G-code system A)",
                                b.words[other].value, w.value));
      (is_motion(w) ? motion : cyc) = i;
    }
    own_axes = own_axes || takes_own_axes(w);
  }
  if (motion != kNoWord) {  // G00-G03, G32 cancel the cycle
    single_ = Single{};
    return true;
  }
  if (cyc == kNoWord && (single_.code == 0 || own_axes || !axes)) return true;
  if (cyc != kNoWord) {
    const int code = static_cast<int>(std::lround(b.words[cyc].value));
    if (code != single_.code) single_ = Single{};
    single_.code = code;
    if (!axes) {  // the mode alone (with its R, F kept): the rest of the block runs
      for (std::size_t i = b.words.size(); i-- > 0;) {
        const grammar::Word& w = b.words[i];
        if (w.letter == 'R') single_.taper = w.value;
        if (w.letter == 'F' && code == 92) single_.lead = w.value;
        if (i == cyc || w.letter == 'R' || (w.letter == 'F' && code == 92))
          b.words.erase(b.words.begin() + static_cast<std::ptrdiff_t>(i));
      }
      return true;
    }
  }
  handled = true;
  const int code = single_.code;
  SourceLoc at = cyc != kNoWord ? b.words[cyc].loc : SourceLoc{b.line, 1};
  if (cyc == kNoWord)
    for (const grammar::Word& w : b.words)
      if (w.letter != 'N') {
        at = w.loc;
        break;
      }
  const grammar::Word* word[26] = {};
  for (std::size_t i = 0; i < b.words.size(); ++i) {
    const grammar::Word& w = b.words[i];
    if (i == cyc || w.letter == 'N') continue;
    if (std::string_view("XZUWRF").find(w.letter) == std::string_view::npos)
      return fail(err, ErrorCode::UnusedWord, w.loc,
                  fmt::format("{}{:g} in a G{} cycle block: the {} cycle takes X (U), Z (W), R "
                              "and F only",
                              w.letter, w.value, code, cycle_title(code)));
    word[w.letter - 'A'] = &w;
  }
  auto has = [&](char c) { return word[c - 'A'] != nullptr; };
  auto get = [&](char c) { return word[c - 'A']->value; };
  for (const auto& [inc, abs] : {std::pair{'U', 'X'}, std::pair{'W', 'Z'}})
    if (has(inc) && has(abs))
      return fail(err, ErrorCode::DuplicateWord, word[inc - 'A']->loc,
                  fmt::format("{} and {} in one block: on a Fanuc lathe {} is {}'s incremental "
                              "word",
                              inc, abs, inc, abs));
  if (s.plane != Plane::XZ)
    return fail(err, ErrorCode::CycleMisused, at,
                fmt::format("G{} needs the ZX plane (G18), the lathe's", code));
  if (s.comp.active())
    return fail(err, ErrorCode::CutterCompMisused, at,
                fmt::format("G{} with tool nose radius compensation on (G41/G42): cancel it with "
                            "G40 first (the compensated single cycles are not modelled)",
                            code));
  const Pos9 p = Frame(s).to_program(s.position_mm);
  const double z0 = p[2] / s.mm_per_unit(), x0 = p[0] / s.mm_per_unit();
  const double xs = s.lathe_diameter ? 0.5 : 1.0;
  // X, Z absolute; U, W from the start point (the cycle's moves end there).
  if (has('X')) single_.xe = get('X') * xs;
  if (has('U')) single_.xe = x0 + get('U') * xs;
  if (has('Z')) single_.ze = get('Z');
  if (has('W')) single_.ze = z0 + get('W');
  single_.has_x = single_.has_x || has('X') || has('U');
  single_.has_z = single_.has_z || has('Z') || has('W');
  if (has('R')) single_.taper = get('R');
  if (has('F') && code == 92) single_.lead = get('F');
  if (!single_.has_x || !single_.has_z)
    return fail(err, ErrorCode::MissingWord, at,
                fmt::format("G{} without {}: the {} cycle needs the end of the cut in X (X or U) "
                            "and Z (Z or W), kept for the blocks that repeat it",
                            code, single_.has_x ? "Z (W)" : "X (U)", cycle_title(code)));
  double feed = -1.0;
  if (has('F') && code != 92) {
    feed = get('F');
    if (!(feed >= 0.0))
      return fail(err, ErrorCode::NegativeFeed, word['F' - 'A']->loc,
                  fmt::format("F{:g} is negative", feed));
  }
  if (code == 92 && !(single_.lead > 0.0))
    return fail(err, ErrorCode::MissingWord, at, "G92 needs F, the thread's lead, more than 0");
  const bool along_z = code != 94;  // G90/G92 cut along Z, G94 across in X
  if (along_z ? std::fabs(single_.ze - z0) < kSameTol : std::fabs(single_.xe - x0) < kSameTol)
    return fail(err, ErrorCode::CycleMisused, at,
                fmt::format("G{}: the cut has no length: its end {} is the start point's", code,
                            along_z ? "Z" : "X"));
  SingleInput in;
  in.code = code;
  in.z0 = z0;
  in.x0 = x0;
  in.ze = single_.ze;
  in.xe = single_.xe;
  in.taper = single_.taper;
  in.f = code == 92 ? single_.lead : feed;
  moves_.clear();
  single_cycle_moves(in, moves_);
  Cycle c;
  c.code = code;
  c.loc = at;
  c.z0 = z0;
  c.x0 = x0;
  cycle_ = std::move(c);
  outcome = Outcome::Moves;
  return true;
}

}  // namespace gm
