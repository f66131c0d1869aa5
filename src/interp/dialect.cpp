// Dialect rules that are not LinuxCNC's: names, grbl's '$' lines and grbl 1.1's accepted set.
#include "interp/dialect.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>

namespace gm {

bool parse_dialect(std::string_view text, Dialect& out) {
  std::string t(text);
  for (char& c : t) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (t == "linuxcnc") {
    out = Dialect::LinuxCNC;
  } else if (t == "fanuc") {
    out = Dialect::Fanuc;
  } else if (t == "grbl") {
    out = Dialect::Grbl;
  } else {
    return false;
  }
  return true;
}

const char* dialect_name(Dialect d) {
  switch (d) {
    case Dialect::Fanuc:
      return "fanuc";
    case Dialect::Grbl:
      return "grbl";
    case Dialect::LinuxCNC:
      break;
  }
  return "linuxcnc";
}

bool grbl_dollar_line(std::string_view text) {
  for (char c : text) {
    if (c == ' ' || c == '\t') continue;
    return c == '$';
  }
  return false;
}

namespace {

// grbl 1.1's G codes (x 10): gnea/grbl README "G-code support" and gcode.c.
constexpr std::array<int, 38> kGrblG = {
    0,   10,  20,  30,  40,  100, 170, 180, 190, 200, 210, 280, 281, 300, 301, 382, 383, 384, 385,
    400, 431, 490, 530, 540, 550, 560, 570, 580, 590, 610, 800, 900, 910, 911, 920, 921, 930, 940};
// grbl 1.1's M codes: program flow, spindle, coolant, M56 (parking override).
constexpr std::array<int, 11> kGrblM = {0, 1, 2, 30, 3, 4, 5, 7, 8, 9, 56};

bool grbl_g(double v) {
  const long n = std::lround(v * 10.0);
  if (std::abs(v * 10.0 - static_cast<double>(n)) > 1e-6) return false;
  return std::find(kGrblG.begin(), kGrblG.end(), n) != kGrblG.end();
}

bool grbl_m(double v) {
  const long n = std::lround(v);
  return std::abs(v - static_cast<double>(n)) < 1e-6 &&
         std::find(kGrblM.begin(), kGrblM.end(), n) != kGrblM.end();
}

}  // namespace

bool grbl_accepts(const grammar::Block& b, SourceLoc& loc, std::string& why) {
  if (b.oword.kind != grammar::OKind::None) {
    loc = b.oword.loc;
    why = b.oword.kind == grammar::OKind::M98 || b.oword.kind == grammar::OKind::M99
              ? "grbl 1.1 has no subprograms (M98/M99)"
              : "grbl 1.1 has no O-words (subroutines, loops, conditions)";
    return false;
  }
  if (!b.assignments.empty()) {
    loc = b.assignments.front().loc;
    why = "grbl 1.1 has no parameters ('#')";
    return false;
  }
  if (!b.word_exprs.empty()) {
    loc = b.words[b.word_exprs.front().word].loc;
    why = "grbl 1.1 has no expressions or parameters: a word takes a plain number";
    return false;
  }
  bool arc = false;
  const grammar::Word* p = nullptr;
  for (const grammar::Word& w : b.words) {
    const char c = w.letter;
    if (c == 'G') {
      if (!grbl_g(w.value)) {
        loc = w.loc;
        why = fmt::format("G{:g} is not in grbl 1.1's G-code", w.value);
        return false;
      }
      if (w.value == 2.0 || w.value == 3.0) arc = true;
    } else if (c == 'M') {
      if (!grbl_m(w.value)) {
        loc = w.loc;
        why = fmt::format("M{:g} is not in grbl 1.1's G-code", w.value);
        return false;
      }
    } else if (std::string_view("FIJKLNPRSTXYZ").find(c) == std::string_view::npos) {
      loc = w.loc;
      why = fmt::format("grbl 1.1 has no {} word",
                        c == '@' || c == '^' ? "polar (@, ^)" : std::string(1, c));
      return false;
    } else if (c == 'P') {
      p = &w;
    }
  }
  if (arc && p != nullptr) {
    loc = p->loc;
    why = "grbl 1.1 arcs take no P (turns): gnea/grbl#1020";
    return false;
  }
  return true;
}

}  // namespace gm
