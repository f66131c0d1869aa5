// The dialects' rules: names, the per-line rules (rs274's line limit, grbl's '$' lines and
// accepted set, Fanuc's machine M codes, the missing program end) and grbl's start in G0.
#include "interp/dialect.hpp"

#include "common/error_codes.hpp"
#include "interp/codes.hpp"

#include <fmt/format.h>

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
  } else if (t == "haas") {
    out = Dialect::Haas;
  } else if (t == "mach3") {
    out = Dialect::Mach3;
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
    case Dialect::Haas:
      return "haas";
    case Dialect::Mach3:
      return "mach3";
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

DialectSet dialect_bit(Dialect d) {
  return static_cast<DialectSet>(1u << static_cast<unsigned>(d));
}

// grbl 1.1's G codes: the code table's rows with the grbl bit.
bool grbl_g(double v) {
  const long n = std::lround(v * 10.0);
  if (std::abs(v * 10.0 - static_cast<double>(n)) > 1e-6) return false;
  const Code* c = n < 0 || n > 9999 ? nullptr : find_code('G', static_cast<int>(n));
  return c != nullptr && (c->dialects & kGrblBit) != 0;
}

// grbl 1.1's M codes: program flow, spindle, coolant (the table's rows with the grbl bit), and
// M56 (parking override), which has no row: the interpreter then refuses it as unknown.
bool grbl_m(double v) {
  const long n = std::lround(v);
  if (!(std::abs(v - static_cast<double>(n)) < 1e-6)) return false;
  if (n == 56) return true;
  const Code* c = n < 0 || n > 999 ? nullptr : find_code('M', static_cast<int>(10 * n));
  return c != nullptr && (c->dialects & kGrblBit) != 0;
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

std::string echoed_line(const std::string& text) {
  return text.size() <= 512 ? text : std::string();
}

bool DialectRules::line_too_long(std::uint64_t bytes, int line, const std::string& text,
                                 std::vector<Diagnostic>& diags) const {
  diags.push_back(Diagnostic{
      Severity::Error, static_cast<int>(ErrorCode::LineTooLong),
      SourceLoc{line, static_cast<int>(kRs274LineBytes) - 1},
      fmt::format("command too long: {} bytes with the line end, LinuxCNC reads at most {} "
                  "(--dialect fanuc has no such limit)",
                  bytes, kRs274LineBytes - 1),
      echoed_line(text)});
  return false;
}

bool DialectRules::grbl_passed_over(const std::string& text, int line,
                                    std::vector<Diagnostic>& diags) {
  if (!grbl_dollar_line(text)) return false;
  if (!dollar_warned_) {  // a grbl setting or command ($H, $$, $110=500): not G-code
    dollar_warned_ = true;
    diags.push_back(Diagnostic{Severity::Warning, 0, SourceLoc{line, 1},
                               "grbl '$' setting and command lines are passed over (the "
                               "first is here)",
                               echoed_line(text)});
  }
  return true;
}

bool DialectRules::grbl_block_accepted(const grammar::Block& block, const std::string& text,
                                       std::vector<Diagnostic>& diags) const {
  SourceLoc at;
  std::string why;
  if (grbl_accepts(block, at, why)) return true;
  diags.push_back(Diagnostic{Severity::Error, static_cast<int>(ErrorCode::NotInDialect), at,
                             why + " (--dialect grbl)", echoed_line(text)});
  return false;
}

bool DialectRules::machine_codes(grammar::Block& block, const std::string& text,
                                 std::vector<Diagnostic>& diags) {
  if (!fanuc_family(dialect_) && dialect_ != Dialect::Mach3) return true;
  auto& words = block.words;
  for (std::size_t i = 0; i < words.size();) {
    const grammar::Word& w = words[i];
    const long m = std::lround(w.value);
    const Code* known = nullptr;
    if (w.letter != 'M' || std::abs(w.value - static_cast<double>(m)) > 1e-6 || m < 0 || m > 99 ||
        ((known = find_code('M', static_cast<int>(10 * m))) != nullptr &&
         (known->dialects & dialect_bit(dialect_)) != 0)) {
      ++i;
      continue;
    }
    if (m == 97) {
      diags.push_back(Diagnostic{Severity::Error, static_cast<int>(ErrorCode::NotInDialect), w.loc,
                                 "M97 (Haas local subprogram call to line N) is not supported: "
                                 "use M98 with an O-numbered subprogram",
                                 echoed_line(text)});
      return false;
    }
    if (!fanuc_warned_[static_cast<std::size_t>(m)]) {
      fanuc_warned_[static_cast<std::size_t>(m)] = true;
      diags.push_back(Diagnostic{Severity::Warning, 0, w.loc,
                                 fmt::format("M{} is a machine function LinuxCNC does not have: "
                                             "passed over (--dialect {}; warned once)",
                                             m, dialect_name(dialect_)),
                                 echoed_line(text)});
    }
    words.erase(words.begin() + static_cast<std::ptrdiff_t>(i));
  }
  return !(words.empty() && block.message_count == 0);
}

void DialectRules::missing_end(int last_line, bool opened_percent, const std::string& last_text,
                               const std::string& file, std::vector<Diagnostic>& diags) const {
  const SourceLoc at{last_line > 0 ? last_line : 1, 1};
  switch (dialect_) {
    case Dialect::Grbl:  // grbl streams: no end
      return;
    case Dialect::Fanuc:
    case Dialect::Haas:
    case Dialect::Mach3:
      diags.push_back(Diagnostic{Severity::Warning, 0, at,
                                 fmt::format("the program ends without M2/M30 (ended here, "
                                             "--dialect {})",
                                             dialect_name(dialect_)),
                                 last_text, file});
      return;
    case Dialect::LinuxCNC:
      break;
  }
  diags.push_back(Diagnostic{Severity::Error, static_cast<int>(ErrorCode::MissingProgramEnd), at,
                             opened_percent
                                 ? "missing program end: no closing '%' (or M2/M30)"
                                 : "missing program end: the program must end with M2 or M30",
                             last_text, file});
}

bool DialectRules::start_block(grammar::Block& block) const {
  if (dialect_ != Dialect::Grbl) return false;
  block.words.push_back(grammar::Word{'G', 0.0, SourceLoc{1, 1}});
  return true;
}

}  // namespace gm
