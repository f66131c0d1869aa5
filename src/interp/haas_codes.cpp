// Haas mill codes LinuxCNC does not have (--dialect haas), rewritten into what the interpreter
// runs: G154 P1-P99, G10 L20 P1-P99, G187, G103, M19 P, M41/M42.
#include "interp/haas_codes.hpp"

#include "common/error_codes.hpp"
#include "interp/block_edit.hpp"
#include "interp/dialect.hpp"
#include "interp/frame.hpp"

#include <fmt/format.h>

#include <cmath>

namespace gm {

namespace {

namespace be = block_edit;

// G59.3 (coordinate system 9, #5381-#5390) carries the selected G154 offsets: Haas mills have
// no G59.1-G59.3.
constexpr int kCarrierSystem = 8;
constexpr int kCarrierFirstParameter = 5221 + 20 * kCarrierSystem;

// P of a G154 or G10 L20: a whole number 1..99.
bool offset_number(const grammar::Word* p, SourceLoc at, const char* what, int& n,
                   InterpError& err) {
  if (p == nullptr)
    return fail(err, ErrorCode::MissingWord, at,
                fmt::format("{} needs P1-P99 (the work offset)", what));
  const double v = std::round(p->value);
  if (std::fabs(p->value - v) > 1e-6 || v < 1 || v > 99)
    return fail(err, ErrorCode::ValueOutOfRange, p->loc,
                fmt::format("{} P{:g}: the work offset is P1-P99", what, p->value));
  n = static_cast<int>(v);
  return true;
}

}  // namespace

bool HaasCodes::local_call(const grammar::Block& block) {
  return be::find_code(block, 'M', 970) != be::kNone;
}

void HaasCodes::warn_once(bool& warned, SourceLoc loc, const std::string& what,
                          const std::string& text, std::vector<Diagnostic>& diags) const {
  if (warned) return;
  warned = true;
  diags.push_back(Diagnostic{Severity::Warning, 0, loc, what + " (--dialect haas; warned once)",
                             echoed_line(text)});
}

void HaasCodes::select(Interpreter& interp, int p) {
  const Pos9& o = offsets_mm_[static_cast<std::size_t>(p - 1)];
  for (int i = 0; i < kProgramAxes; ++i)
    interp.write_system_parameter(kCarrierFirstParameter + i, o[i]);
  interp.write_system_parameter(kCarrierFirstParameter + 9, 0.0);
  active_ = p;
}

// G154 Pn: select work offset n (Haas: G154 P1-P99, "additional work offsets").
bool HaasCodes::g154(grammar::Block& block, std::size_t at, Interpreter& interp, InterpError& err) {
  const SourceLoc loc = block.words[at].loc;
  int p = 0;
  if (!offset_number(be::word(block, 'P'), loc, "G154", p, err)) return false;
  if (interp.state().coord_system == kCarrierSystem) {
    // G59.3 again would keep the offsets it took (LinuxCNC): G54 first, as its own block.
    grammar::Block leave;
    leave.line = block.line;
    leave.words.push_back(grammar::Word{'G', 54.0, loc});
    std::vector<Canon> none;
    if (!interp.execute(leave, none, err)) return false;
  }
  select(interp, p);
  be::erase_letter(block, 'P');
  block.words[be::find_code(block, 'G', 1540)].value = 59.3;
  return true;
}

// G10 L20 Pn X Y Z ...: work offset n's origin in machine coordinates (G90), or moved by the
// words (G91); the Haas G10 page: "P1-P99 G154 P1-P99 reference auxiliary coordinate (L20)".
bool HaasCodes::g10_l20(grammar::Block& block, Interpreter& interp, InterpError& err) {
  const std::size_t g10 = be::find_code(block, 'G', 100);
  int p = 0;
  if (!offset_number(be::word(block, 'P'), block.words[g10].loc, "G10 L20", p, err)) return false;
  const ModalState& s = interp.state();
  bool incremental = s.incremental;
  if (be::find_code(block, 'G', 910) != be::kNone) incremental = true;
  if (be::find_code(block, 'G', 900) != be::kNone) incremental = false;
  Pos9& o = offsets_mm_[static_cast<std::size_t>(p - 1)];
  const double unit = s.inch ? 25.4 : 1.0;
  const bool in_effect = active_ == p && s.coord_system == kCarrierSystem;
  for (int a = 0; a < kProgramAxes; ++a) {
    const std::size_t i = be::find(block, kProgramAxisLetters[static_cast<std::size_t>(a)]);
    if (i == be::kNone) continue;
    const double per = axis_is_rotary(a) ? 1.0 : unit;
    const double v = block.words[i].value * per;
    o[a] = incremental ? o[a] + v : v;
    // In effect: G10 L2 P9 sets G59.3, which carries it, and the interpreter takes it at once.
    if (in_effect)
      block.words[i].value = o[a] / per;
    else
      be::erase(block, i);
  }
  if (in_effect) {
    block.words[be::find(block, 'L')].value = 2.0;
    block.words[be::find(block, 'P')].value = 9.0;
    return true;
  }
  be::erase(block, g10);
  be::erase_letter(block, 'L');
  be::erase_letter(block, 'P');
  return true;
}

bool HaasCodes::apply(grammar::Block& block, Interpreter& interp, const std::string& text,
                      std::vector<Canon>& out, std::vector<Diagnostic>& diags, InterpError& err) {
  bool any = false;  // (most blocks have none of these: looked at once)
  for (const grammar::Word& w : block.words) {
    const double v = w.value;
    if (w.letter == 'G')
      any = any || v == 154.0 || v == 10.0 || v == 187.0 || v == 103.0 ||
            (active_ != 0 && v >= 54.0 && v <= 59.35);
    else if (w.letter == 'M')
      any = any || v == 19.0 || v == 41.0 || v == 42.0;
  }
  if (!any) return true;
  if (const std::size_t i = be::find_code(block, 'G', 1540); i != be::kNone) {
    if (!g154(block, i, interp, err)) return false;
  } else if (be::find_code(block, 'G', 100) != be::kNone) {
    const grammar::Word* l = be::word(block, 'L');
    if (l != nullptr && l->value == 20.0 && !g10_l20(block, interp, err)) return false;
  } else if (active_ != 0) {  // another work offset selected: G154 is no longer in effect
    for (const grammar::Word& w : block.words)
      if (w.letter == 'G' && w.value >= 54.0 && w.value <= 59.35) active_ = 0;
  }
  if (const std::size_t i = be::find_code(block, 'G', 1870); i != be::kNone) {
    // G187 P1-P3 (rough, medium, finish: Setting 191's smoothness) E (corner accuracy): E is
    // the path tolerance LinuxCNC's G64 P is; P is not modelled.
    const grammar::Word* e = be::word(block, 'E');
    const grammar::Word* p = be::word(block, 'P');
    const double tol = e != nullptr ? e->value : -1.0;
    if (p != nullptr)
      warn_once(smoothness_warned_, p->loc,
                fmt::format("G187 P{:g} (smoothness) is not modelled: only E (the corner "
                            "tolerance, as G64 P) is",
                            p->value),
                text, diags);
    be::erase_letter(block, 'P');
    be::erase_letter(block, 'E');
    block.words[be::find_code(block, 'G', 1870)].value = 64.0;
    if (tol >= 0.0) block.words.push_back(grammar::Word{'P', tol, e->loc});
  }
  if (const std::size_t i = be::find_code(block, 'G', 1030); i != be::kNone) {
    warn_once(lookahead_warned_, block.words[i].loc,
              "G103 (block look-ahead limit) is passed over: gmotion reads the whole program", text,
              diags);
    be::erase(block, i);
    be::erase_letter(block, 'P');
  }
  if (const std::size_t i = be::find_code(block, 'M', 190); i != be::kNone) {
    // Haas M19 P (or R): the angle. LinuxCNC's M19 takes the angle in R (its P is a direction).
    if (const std::size_t p = be::find(block, 'P');
        p != be::kNone && be::find(block, 'R') == be::kNone)
      block.words[p].letter = 'R';
    (void)i;
  }
  for (const int gear : {41, 42}) {  // low/high gear override: recorded, no motion
    const std::size_t i = be::find_code(block, 'M', 10 * gear);
    if (i == be::kNone) continue;
    out.emplace_back(Event{block.line, EventKind::UserMcode, {}, gear});
    be::erase(block, i);
  }
  return true;
}

}  // namespace gm
