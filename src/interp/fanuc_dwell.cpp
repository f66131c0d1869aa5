// Fanuc's and Haas's dwell P (G04 and the drilling cycles' dwell at the bottom), rewritten into
// LinuxCNC's seconds: one rule for the time a P word gives (docs/dialects.md, "G04 dwell").
#include "common/error_codes.hpp"
#include "interp/codes.hpp"
#include "interp/dialect.hpp"

#include <fmt/format.h>

#include <cmath>

namespace gm {

namespace {

// The drilling cycles LinuxCNC reads on a mill (G73, G74, G81-G89): the P of G82, G86, G88,
// G89 and the taps' G74, G84 is their dwell at the bottom; the others keep P as the sticky
// dwell of the cycles after them, so it is read alike.
bool drilling_cycle(int number10) {
  return number10 == 730 || number10 == 740 || (number10 >= 810 && number10 <= 890);
}

// The code x 10 of G or M word `w` (G82 = 820), -1 out of the codes' range (named apart from
// fanuc_modal.cpp's code10: the unity build may put both in one unit).
int dwell_code10(const grammar::Word& w) {
  const double t = w.value * 10.0;
  return t >= 0.0 && t < 1e5 ? static_cast<int>(std::lround(t)) : -1;
}

// Another code of the block than a drilling cycle takes P (G10 L2 P1, G64 P, M66 P, ...), or
// moves (G0-G3, G76, ...): the P is not the cycle's.
bool p_of_another_code(const grammar::Block& block) {
  for (const grammar::Word& w : block.words) {
    if (w.letter != 'G' && w.letter != 'M') continue;
    const int n = dwell_code10(w);
    if (w.letter == 'G' && drilling_cycle(n)) continue;
    const Code* c = find_code(w.letter, n);
    if (c != nullptr &&
        ((c->word_mask & letter_mask("P")) != 0 || (w.letter == 'G' && c->group == Group::Motion)))
      return true;
  }
  return false;
}

}  // namespace

// The one rule: a P without a decimal point is milliseconds (P1500 = 1.5 s); with a point Haas
// reads seconds (P1.5 = 1.5 s) and Fanuc refuses it (its P takes no decimal point). `code` names
// the code the P belongs to; `or_x`: it also takes X in seconds (G04).
bool DialectRules::dwell_p(grammar::Word& p, const std::string& code, bool or_x,
                           const std::string& text, std::vector<Diagnostic>& diags) const {
  if (!p.decimal_point) {
    p.value /= 1000.0;  // P2000: milliseconds
    return true;
  }
  if (dialect_ == Dialect::Haas) return true;  // Haas: P2.5 is seconds
  const std::string alternative = or_x ? fmt::format("P{:g} or X{:g}", p.value * 1000.0, p.value)
                                       : fmt::format("P{:g}", p.value * 1000.0);
  diags.push_back(Diagnostic{Severity::Error, static_cast<int>(ErrorCode::NotInDialect), p.loc,
                             fmt::format("{} P{:g}: Fanuc's P is milliseconds without a decimal "
                                         "point (write {})",
                                         code, p.value, alternative),
                             echoed_line(text)});
  return false;
}

bool DialectRules::fanuc_dwell(grammar::Block& block, bool lathe, int motion,
                               const std::string& text, std::vector<Diagnostic>& diags) const {
  if (!fanuc_family(dialect_)) return true;
  for (const grammar::Word& w : block.words)
    if (w.letter == 'P' || (w.letter == 'G' && w.value == 4.0))
      return dwell_words(block, lathe, motion, text, diags);
  return true;
}

// A block with a P or a G04: the G04's time, or a drilling cycle's P. Kept out of line: the scan
// above, run on every block, then saves no registers.
[[gnu::noinline]] bool DialectRules::dwell_words(grammar::Block& block, bool lathe, int motion,
                                                 const std::string& text,
                                                 std::vector<Diagnostic>& diags) const {
  grammar::Word* p = nullptr;
  bool g04 = false;
  for (grammar::Word& w : block.words) {
    if (w.letter == 'P') p = &w;
    g04 = g04 || (w.letter == 'G' && w.value == 4.0);
  }
  if (g04) return g04_dwell(block, p, lathe, text, diags);
  // A drilling cycle's P on a mill (a lathe's G74 P is a peck's width, its drilling cycles are
  // refused), in the cycle's block or a later block of holes under it.
  if (p == nullptr || lathe || block.oword.kind != grammar::OKind::None) return true;
  int cycle = motion;
  for (const grammar::Word& w : block.words)
    if (w.letter == 'G' && drilling_cycle(dwell_code10(w))) cycle = dwell_code10(w);
  if (!drilling_cycle(cycle)) return true;
  if (p_of_another_code(block)) return true;
  return dwell_p(*p, code_name('G', cycle), false, text, diags);
}

// G04: P as the rule above; X (U on a lathe) seconds, with or without a point.
bool DialectRules::g04_dwell(grammar::Block& block, grammar::Word* p, bool lathe,
                             const std::string& text, std::vector<Diagnostic>& diags) const {
  grammar::Word* seconds = nullptr;  // X, or U on a lathe
  for (grammar::Word& w : block.words)
    if ((w.letter == 'X' || (lathe && w.letter == 'U')) && seconds == nullptr) seconds = &w;
  if (p != nullptr && seconds != nullptr) {
    diags.push_back(Diagnostic{Severity::Error, static_cast<int>(ErrorCode::NotInDialect),
                               seconds->loc,
                               fmt::format("G04 with both P and {}: one dwell time (--dialect {})",
                                           seconds->letter, dialect_name(dialect_)),
                               echoed_line(text)});
    return false;
  }
  if (seconds != nullptr) {  // G04 X2.5 / U2.5: seconds, run as LinuxCNC's G4 P2.5
    seconds->letter = 'P';
    return true;
  }
  if (p == nullptr) return true;  // (the interpreter's "G4 without P")
  return dwell_p(*p, "G04", true, text, diags);
}

}  // namespace gm
