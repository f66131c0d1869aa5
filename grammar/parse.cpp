// The grammar facade: compacts a line (LinuxCNC spacing rules), runs the X3 block rule over it,
// converts numbers, and turns every failure into a located SyntaxError with resynchronisation.
#include "grammar/parse.hpp"

#include "grammar/compact_line.hpp"
#include "grammar/decimal_scan.hpp"
#include "grammar/parse_items.hpp"
#include "grammar/plain_words.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>

namespace gm::grammar {

namespace {

bool starts_item(char c) {
  return (c >= 'A' && c <= 'Z') || c == '(' || c == ';';
}

std::string describe_char(char c) {
  const auto u = static_cast<unsigned char>(c);
  if (u >= 0x21 && u < 0x7f) return std::string("'") + c + "'";
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%02X", u);
  return buf;
}

// Shortens long numbers for messages: the first digits and the total count.
std::string show_number(std::string_view s) {
  if (s.size() <= 24) return std::string(s);
  return std::string(s.substr(0, 12)) + "...(" + std::to_string(s.size()) + " characters)";
}

// digits [. digits] (no sign, no exponent) with at most 15 digits after the leading zeros, by
// one exact division (grammar/decimal_scan.hpp). False: take the general path.
bool fast_decimal(std::string_view s, double& value) {
  const char* p = s.data();
  const char* const end = p + s.size();
  const DecimalScan d = scan_decimal(p, end);
  return p == end && exact_decimal(d, value);  // nothing left: no sign, exponent or second point
}

// Converts the number text [sign] digits [. digits] [E [sign] digits]. Returns false if the
// value does not fit a finite double; `has_exponent` reports an exponent part.
bool to_double(std::string_view s, double& value, bool& has_exponent) {
  bool negative = false;
  if (!s.empty() && (s.front() == '+' || s.front() == '-')) {
    negative = s.front() == '-';
    s.remove_prefix(1);
  }
  has_exponent = s.find('E') != std::string_view::npos;
  if (!has_exponent && fast_decimal(s, value)) {
    if (negative) value = -value;
    return true;
  }
  double v = 0.0;
  auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v, std::chars_format::general);
  if (ec == std::errc::result_out_of_range) {
    // Underflow (a tiny number written out) is zero to every machine; overflow is an error.
    const auto first_nonzero = s.find_first_not_of("0.");
    const auto point = s.find('.');
    const bool below_one = first_nonzero == std::string_view::npos ||
                           (point != std::string_view::npos && point < first_nonzero);
    if (below_one && !has_exponent) {
      value = 0.0;
      return true;
    }
    return false;
  }
  if (ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(v)) return false;
  value = negative ? -v : v;
  return true;
}

// Skips a '[...]' expression or a '#<name>' parameter so their contents make no further errors.
const char* skip_unsupported(const char* pos, const char* end) {
  if (pos == end) return pos;
  if (*pos == '[') {
    int depth = 0;
    while (pos != end) {
      if (*pos == '[') ++depth;
      if (*pos == ']' && --depth == 0) break;
      ++pos;
    }
  } else if (*pos == '#' && pos + 1 != end && pos[1] == '<') {
    while (pos != end && *pos != '>') ++pos;
  }
  return pos;
}

// Appends the name written at [first, last) to out.names in lower case.
void add_name(Block& out, const char* begin, int first, int last, std::uint32_t& name,
              std::uint32_t& size) {
  name = static_cast<std::uint32_t>(out.names.size());
  size = static_cast<std::uint32_t>(last - first);
  for (int k = first; k < last; ++k) {
    char ch = begin[k];
    if (ch >= 'A' && ch <= 'Z') ch = static_cast<char>(ch - 'A' + 'a');
    out.names.push_back(ch);
  }
}

// The O-word keyword `word` (upper case), or None.
OKind oword_keyword(std::string_view word) {
  static constexpr std::pair<std::string_view, OKind> kKeywords[] = {
      {"SUB", OKind::Sub},
      {"ENDSUB", OKind::EndSub},
      {"CALL", OKind::Call},
      {"RETURN", OKind::Return},
      {"IF", OKind::If},
      {"ELSEIF", OKind::ElseIf},
      {"ELSE", OKind::Else},
      {"ENDIF", OKind::EndIf},
      {"WHILE", OKind::While},
      {"ENDWHILE", OKind::EndWhile},
      {"DO", OKind::Do},
      {"REPEAT", OKind::Repeat},
      {"ENDREPEAT", OKind::EndRepeat},
      {"BREAK", OKind::Break},
      {"CONTINUE", OKind::Continue}};
  for (const auto& [name, kind] : kKeywords)
    if (word == name) return kind;
  return OKind::None;
}

}  // namespace

const char* okind_name(OKind k) {
  constexpr const char* kNames[] = {
      "",      "sub",          "endsub", "call",     "return", "if",          "elseif",
      "else",  "endif",        "while",  "endwhile", "do",     "repeat",      "endrepeat",
      "break", "continue",     "",       "M98",      "M99",    "IF ... GOTO", "IF ... THEN",
      "GOTO",  "WHILE ... DO", "DO",     "END",      "G65"};
  return kNames[static_cast<int>(k)];
}

bool BlockParser::parse_oword(Block& out, std::string_view compact, std::size_t k,
                              std::size_t& after) {
  OWord& o = out.oword;
  o.loc = SourceLoc{line_, columns_[k]};
  o.label.clear();
  o.label_expr = false;
  std::size_t p = k + 1;
  if (p < compact.size() && (compact[p] == '[' || compact[p] == '#')) {
    // O[#2*10], o#<name>: the number is an expression or a parameter (rs274 2.9), kept as the
    // first argument (one bracket only: `O[a][b] call` is refused).
    const char* pos = compact.data() + p;
    ItemFailure number_fail;
    const bool parsed =
        compact[p] == '['
            ? parse_oword_args(pos, compact.data() + compact.size(), ast_, number_fail)
            : parse_oword_param(pos, compact.data() + compact.size(), ast_, number_fail);
    if (!parsed || ast_.args.size() != 1) {
      add_error(out, ErrorCode::BadOWord, static_cast<int>(p),
                "bad expression for the O-word number");
      return false;
    }
    o.named = false;
    o.label_expr = true;
    p = static_cast<std::size_t>(pos - compact.data());
  } else if (p < compact.size() && compact[p] == '<') {
    const std::size_t close = compact.find('>', p + 1);
    if (close == std::string_view::npos || close == p + 1) {
      add_error(out, ErrorCode::BadOWord, static_cast<int>(p),
                close == std::string_view::npos ? "O-word name not closed: expected '>'"
                                                : "empty O-word name");
      return false;
    }
    o.named = true;
    for (std::size_t i = p + 1; i < close; ++i) {
      char ch = compact[i];
      if (ch >= 'A' && ch <= 'Z') ch = static_cast<char>(ch - 'A' + 'a');
      o.label.push_back(ch);
    }
    p = close + 1;
  } else if (p < compact.size() && compact[p] >= '0' && compact[p] <= '9') {
    o.named = false;
    while (p < compact.size() && compact[p] == '0') ++p;
    while (p < compact.size() && compact[p] >= '0' && compact[p] <= '9')
      o.label.push_back(compact[p++]);
    if (o.label.empty()) o.label.push_back('0');  // not = "0": a false -Wrestrict in g++ 12 -O3
  } else {
    add_error(out, ErrorCode::BadOWord, static_cast<int>(p),
              "an O-word needs a number or a <name> after 'O'");
    return false;
  }
  const std::size_t kw = p;
  while (p < compact.size() && compact[p] >= 'A' && compact[p] <= 'Z') ++p;
  const std::string_view word = compact.substr(kw, p - kw);
  o.kind = oword_keyword(word);
  if (o.kind == OKind::None && word.empty() &&
      (p == compact.size() || compact[p] == '(' || compact[p] == ';')) {
    o.kind = OKind::Program;  // `O1234 (title)`: LinuxCNC's Fanuc-style program number
    after = p;
    return true;
  }
  if (o.kind == OKind::None) {
    add_error(out, ErrorCode::BadOWord, static_cast<int>(kw),
              word.empty() ? "expected an O-word keyword (sub, call, if, while, ...)"
                           : "unknown O-word keyword '" + std::string(word) + "'");
    return false;
  }
  const char* pos = compact.data() + p;
  ItemFailure fail;
  const char* const end = compact.data() + compact.size();
  for (;;) {
    if (!parse_oword_args(pos, end, ast_, fail)) {
      const int off = static_cast<int>(fail.where - compact.data());
      add_error(out, fail.code == ErrorCode::ExpectedNumber ? ErrorCode::BadExpression : fail.code,
                off,
                fail.code == ErrorCode::UnclosedBracket
                    ? std::string("expected ']' to close the O-word argument")
                    : std::string("bad expression in the O-word argument"));
      o.kind = OKind::None;
      return false;
    }
    // A comment between two arguments (`[1] (note) [2]`) is passed over, as rs274 does.
    if (pos == end || *pos != '(') break;
    const char* close = pos + 1;
    while (close != end && *close != ')' && *close != '(') ++close;
    if (close == end || *close != ')' || close + 1 == end || close[1] != '[') break;
    pos = close + 1;
  }
  after = static_cast<std::size_t>(pos - compact.data());
  return true;
}

void BlockParser::add_error(Block& out, ErrorCode code, int offset, std::string message) {
  if (out.errors.size() >= kMaxErrorsPerLine) return;
  const int col = columns_[static_cast<std::size_t>(offset)];
  out.errors.push_back(SyntaxError{code, SourceLoc{line_, col}, std::move(message)});
}

// The phases of a line, in order. Each phase on the path of every line is always inlined: the
// phases are named for the reader, and the parse of a line stays one function for the compiler
// (the hot loop of a check; separate calls cost 2 % of a check's instructions).
template <bool kMacroB>
[[gnu::always_inline]] inline void BlockParser::parse_line(std::string_view text, int line,
                                                           Block& out) {
  line_ = line;
  clear_block(out);
  if constexpr (kMacroB) {
    out.sequence = -1;
    out.remark.clear();
  }
  if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
  if constexpr (!kMacroB) {  // (Macro B reads a sequence number and statements at the start)
    // Most lines are words of letters and plain numbers between blanks: read as they stand, from
    // a copy with room to read numbers 8 bytes at a time.
    if (plain_fast_path_ && read_plain_line(padded_copy(text), line_, out.words)) return;
    out.words.clear();
  }
  const std::string_view compact = compact_line(text);
  std::size_t start = 0;
  if (!read_line_start<kMacroB>(out, compact, start)) return;
  // Most lines are letters and plain numbers only: read without the block rule, the same words.
  if (plain_fast_path_ && out.oword.kind == OKind::None &&
      read_plain_words(compact, start, columns_.data(), line_, out.words))
    return;
  out.words.clear();
  read_items(out, compact, start);
  convert(out, compact.data());
  active_comment(out, compact.data());
}

void BlockParser::parse(std::string_view text, int line, Block& out) {
  if (macro_b_) {
    parse_macro_b(text, line, out);
    return;
  }
  parse_line<false>(text, line, out);
}

// Fanuc Macro B's lines apart: the LinuxCNC parse above is compiled without its statements.
[[gnu::noinline]] void BlockParser::parse_macro_b(std::string_view text, int line, Block& out) {
  parse_line<true>(text, line, out);
}

[[gnu::always_inline]] inline SourceLoc BlockParser::loc_at(int offset) const {
  return SourceLoc{line_, columns_[static_cast<std::size_t>(offset)]};
}

[[gnu::always_inline]] inline void BlockParser::clear_block(Block& out) const {
  out.line = line_;
  out.block_delete = false;
  out.percent = false;
  out.percent_text = false;
  out.words.clear();
  out.message_count = 0;
  out.directive_count = 0;
  out.ops.clear();
  out.word_exprs.clear();
  out.assignments.clear();
  out.names.clear();
  out.oword.kind = OKind::None;
  out.oword.label_expr = false;  // else an M98 line after an O[expr] line read a stale number
  out.oword.args.clear();
  out.errors.clear();
}

static_assert(kCompactSlack >= kDecimalReadAhead);

// The line copied into compact_ with kDecimalReadAhead bytes to spare (zeros) after it.
[[gnu::always_inline]] inline std::string_view BlockParser::padded_copy(std::string_view text) {
  if (compact_.size() < text.size() + kCompactSlack) compact_.resize(text.size() + kCompactSlack);
  std::memcpy(compact_.data(), text.data(), text.size());
  std::memset(compact_.data() + text.size(), 0, kDecimalReadAhead);
  return std::string_view(compact_.data(), text.size());
}

// 1. Compact: drop spaces/tabs outside comments, upper-case letters outside comments.
// Written through pointers into buffers sized once for the line (the hot loop of a check).
// The buffers only grow (a resize down and up again would zero-fill them on every line).
// kCompactSlack to spare: the plain lines' compaction stores 16 characters at a time.
[[gnu::always_inline]] inline std::string_view BlockParser::compact_line(std::string_view text) {
  if (compact_.size() < text.size() + kCompactSlack) compact_.resize(text.size() + kCompactSlack);
  if (columns_.size() < text.size() + 1 + kCompactSlack)
    columns_.resize(text.size() + 1 + kCompactSlack);
  char* cp = compact_.data();
  int* colp = columns_.data();
  const bool plain = std::memchr(text.data(), '(', text.size()) == nullptr &&
                     std::memchr(text.data(), ';', text.size()) == nullptr;
  if (plain) compact_plain_line(text, cp, colp);  // no comment: every character is code
  enum class State { Code, Paren, Rest } state = State::Code;
  for (std::size_t i = 0; !plain && i < text.size(); ++i) {
    char c = text[i];
    if (state == State::Code) {
      if (c == ' ' || c == '\t') continue;
      if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
      if (c == '(') state = State::Paren;
      if (c == ';') state = State::Rest;
    } else if (state == State::Paren && c == ')') {
      state = State::Code;
    }
    *cp++ = c;
    *colp++ = static_cast<int>(i) + 1;
  }
  *colp++ = static_cast<int>(text.size()) + 1;  // end-of-line position
  return std::string_view(compact_.data(), static_cast<std::size_t>(cp - compact_.data()));
}

// The line's start: '/' (block delete), '%', then, after an optional N word, an O-word line
// `O<label> keyword [args]` (comments may follow) or M98/M99 first on the line. `start` is
// where the items begin. False when the O-word is malformed: the line is not parsed further.
template <bool kMacroB>
[[gnu::always_inline]] inline bool BlockParser::read_line_start(Block& out,
                                                                std::string_view compact,
                                                                std::size_t& start) {
  start = 0;
  if (!compact.empty() && compact[0] == '/') {
    out.block_delete = true;
    start = 1;
  }
  if (start < compact.size() && compact[start] == '%') {
    out.percent = true;
    if (start + 1 < compact.size()) {  // rs274 2.9: "Bad character '%' used", one error
      out.percent_text = true;
      add_error(out, ErrorCode::UnexpectedCharacter, static_cast<int>(start),
                "bad character '%' used: a '%' line holds nothing else (--dialect fanuc passes "
                "the text after it over)");
      return false;
    }
    ++start;
  }
  ast_.reset(compact.data());
  std::size_t k = start;
  if (k < compact.size() && compact[k] == 'N')
    for (++k; k < compact.size() && ((compact[k] >= '0' && compact[k] <= '9') || compact[k] == '.');
         ++k) {
    }
  if constexpr (kMacroB) {  // Fanuc Macro B: the sequence number, then IF, GOTO, WHILE, DO, END,
                            // G65, ':'
    if (!read_macro_statement(out, compact, k, start)) {
      out.oword.kind = OKind::None;
      return false;
    }
    if (out.oword.kind != OKind::None) return true;
  }
  if (k < compact.size() && compact[k] == 'O') {
    std::size_t after = 0;
    if (!parse_oword(out, compact, k, after)) return false;
    start = after;
  } else if (k + 2 < compact.size() && compact[k] == 'M') {
    read_flow_m_code(out, compact, k);
  }
  return true;
}

namespace {
bool at(std::string_view compact, std::size_t k, std::string_view word) {
  if (k >= compact.size() || compact[k] != word[0]) return false;  // most lines: one compare
  return compact.substr(k, word.size()) == word;
}
bool is_digit(std::string_view compact, std::size_t k) {
  return k < compact.size() && compact[k] >= '0' && compact[k] <= '9';
}
}  // namespace

// One argument of a Macro B statement at `p`: `[expression]`, `#variable` or a number (GOTO's
// target), appended to out.oword.args' source (ast_.args). False with the error.
bool BlockParser::macro_arg(Block& out, std::string_view compact, std::size_t& p,
                            const char* what) {
  const char* pos = compact.data() + p;
  const char* const end = compact.data() + compact.size();
  const std::size_t before = ast_.args.size();
  ItemFailure fail;
  bool ok = false;
  if (p < compact.size() && compact[p] == '[') {
    ok = parse_oword_args(pos, end, ast_, fail) && ast_.args.size() == before + 1;
  } else if (p < compact.size() && compact[p] == '#') {
    ok = parse_oword_param(pos, end, ast_, fail);
  } else if (is_digit(compact, p)) {
    std::size_t q = p;
    while (is_digit(compact, q)) ++q;
    const int first = static_cast<int>(p), last = static_cast<int>(q);
    ast_.args.push_back(
        ast::Block::Arg{static_cast<int>(ast_.ops.size()), static_cast<int>(ast_.ops.size()) + 1});
    ast_.ops.push_back(ast::ExprOp{Op::Number, first, last});
    pos = compact.data() + q;
    ok = true;
  }
  if (!ok) {
    add_error(out, ErrorCode::BadExpression,
              static_cast<int>(fail.where != nullptr ? fail.where - compact.data() : p),
              std::string("expected [expression], #variable or a number ") + what);
    return false;
  }
  p = static_cast<std::size_t>(pos - compact.data());
  return true;
}

// Fanuc Macro B's statements at `k` (after an optional N): IF [c] GOTO n, IF [c] THEN #i = e,
// GOTO n, WHILE [c] DO m, DO m, END m (FANUC 16i/18i-MB operator's manual B-63534EN, II-15.5),
// G65 (II-15.6.1) and `:1234` (the program number's tape form). out.oword.kind stays None when the
// line is none of these. False (with the error) when one is malformed.
[[gnu::noinline]] bool BlockParser::read_macro_statement(Block& out, std::string_view compact,
                                                         std::size_t k, std::size_t& start) {
  if (k > start) {  // the sequence number N (its fraction, N10.1, is dropped)
    long n = 0;
    for (std::size_t d = start + 1; d < k && compact[d] != '.'; ++d)
      if (n < 100000000) n = n * 10 + (compact[d] - '0');
    out.sequence = n;
  }
  OWord& o = out.oword;
  const auto begin = [&](OKind kind) {
    o.kind = kind;
    o.loc = SourceLoc{line_, columns_[k]};
    o.named = false;
    o.label_expr = false;
    o.label.clear();
  };
  const auto loop_number = [&](std::size_t& p, const char* what) {
    if (!is_digit(compact, p)) {
      add_error(out, ErrorCode::BadOWord, static_cast<int>(p),
                std::string("expected the loop number (1, 2 or 3) after ") + what);
      return false;
    }
    const std::size_t first = p;
    long m = 0;
    while (is_digit(compact, p)) {
      if (m < 1000) m = m * 10 + (compact[p] - '0');
      ++p;
    }
    if (m < 1 || m > 3) {
      add_error(out, ErrorCode::BadOWord, static_cast<int>(first - std::strlen(what)),
                std::string(what) + std::to_string(m) +
                    ": the loop number is 1, 2 or 3 (Fanuc: WHILE [...] DO m ... END m)");
      return false;
    }
    o.label = std::to_string(m);
    return true;
  };
  std::size_t p = k;
  if (p < compact.size() && compact[p] == ':') {  // `:1234`, Fanuc's tape form of O1234
    std::size_t after = 0;
    if (!parse_oword(out, compact, k, after)) return false;
    if (o.kind != OKind::Program) {
      add_error(out, ErrorCode::BadOWord, static_cast<int>(k),
                "':' opens a program number (:1234), nothing else");
      return false;
    }
    start = after;
    return true;
  }
  if (at(compact, p, "IF[")) {
    begin(OKind::IfGoto);
    p += 2;
    if (!macro_arg(out, compact, p, "after IF")) return false;
    if (at(compact, p, "GOTO")) {
      p += 4;
      if (!macro_arg(out, compact, p, "after GOTO")) return false;
    } else if (at(compact, p, "THEN")) {
      o.kind = OKind::IfThen;
      p += 4;
    } else {
      add_error(out, ErrorCode::BadOWord, static_cast<int>(p),
                "expected GOTO or THEN after IF [condition]");
      return false;
    }
  } else if (at(compact, p, "GOTO")) {
    begin(OKind::Goto);
    p += 4;
    if (!macro_arg(out, compact, p, "after GOTO")) return false;
  } else if (at(compact, p, "WHILE[")) {
    begin(OKind::WhileDo);
    p += 5;
    if (!macro_arg(out, compact, p, "after WHILE")) return false;
    if (!at(compact, p, "DO")) {
      add_error(out, ErrorCode::BadOWord, static_cast<int>(p),
                "expected DO m after WHILE [condition]");
      return false;
    }
    p += 2;
    if (!loop_number(p, "DO")) return false;
  } else if (at(compact, p, "DO") && is_digit(compact, p + 2)) {
    begin(OKind::MacroDo);
    p += 2;
    if (!loop_number(p, "DO")) return false;
  } else if (at(compact, p, "END") && is_digit(compact, p + 3)) {
    begin(OKind::EndDo);
    p += 3;
    if (!loop_number(p, "END")) return false;
  } else if (p < compact.size() && compact[p] == 'G') {
    std::size_t d = p + 1;
    while (d < compact.size() && compact[d] == '0') ++d;
    if (at(compact, d, "65") && !is_digit(compact, d + 2) &&
        !(d + 2 < compact.size() && compact[d + 2] == '.'))
      begin(OKind::G65);  // the words, G65 included, are read as items
    return true;
  } else {
    return true;
  }
  start = p;
  return true;
}

// M98/M99 first on the line are control flow (LinuxCNC read_o): M0098 too.
void BlockParser::read_flow_m_code(Block& out, std::string_view compact, std::size_t k) {
  std::size_t d = k + 1;
  while (d < compact.size() && compact[d] == '0') ++d;
  if (d + 1 < compact.size() && compact[d] == '9' &&
      (compact[d + 1] == '8' || compact[d + 1] == '9') &&
      (d + 2 == compact.size() ||
       !((compact[d + 2] >= '0' && compact[d + 2] <= '9') || compact[d + 2] == '.'))) {
    out.oword.kind = compact[d + 1] == '8' ? OKind::M98 : OKind::M99;
    out.oword.loc = SourceLoc{line_, columns_[k]};
    out.oword.named = false;
    out.oword.label.clear();
  }
}

// 2. Parse items, resynchronising after each error at the next letter, '(' or ';'.
[[gnu::always_inline]] inline void BlockParser::read_items(Block& out, std::string_view compact,
                                                           std::size_t start) {
  const char* const begin = compact.data();
  const char* const end = begin + compact.size();
  const char* pos = begin + start;
  while (pos != end && out.errors.size() < kMaxErrorsPerLine) {
    ItemFailure fail;
    const char* item_start = pos;
    if (parse_items(pos, end, ast_, fail)) {
      if (pos == end) break;
      report_stray_character(out, begin, pos);
      pos = skip_unsupported(pos, end);
    } else if (ast_.open == ast::Open::Word || ast_.open == ast::Open::Assign) {
      pos = drop_failed_item(out, begin, end, fail);
    } else {
      drop_open_comment(out, begin, fail);
      break;  // the rest of the line is comment text of unknown extent
    }
    // Resynchronise: next item start after the failure point.
    if (pos == item_start || (pos != end && !starts_item(*pos))) ++pos;
    while (pos != end && !starts_item(*pos)) ++pos;
  }

  if (out.oword.kind != OKind::None) [[unlikely]]
    check_oword_items(out, compact);
}

// What may follow an O-word (comments), M98/M99 and G65 (words), IF ... THEN (one setting).
[[gnu::noinline]] void BlockParser::check_oword_items(Block& out, std::string_view compact) {
  const OKind kind = out.oword.kind;
  if (kind == OKind::IfThen && (ast_.word_count > 0 || ast_.assigns.empty())) {
    add_error(out, ErrorCode::BadOWord,
              ast_.word_count > 0 ? ast_.words[0].id_first : static_cast<int>(compact.size()),
              "IF [condition] THEN takes one setting, #i = expression");
  } else if (kind != OKind::M98 && kind != OKind::M99 && kind != OKind::G65 &&
             kind != OKind::IfThen && (ast_.word_count > 0 || !ast_.assigns.empty())) {
    const int at = ast_.word_count > 0 ? ast_.words[0].id_first : ast_.assigns[0].pos;
    add_error(out, ErrorCode::BadOWord, at, "nothing but comments may follow an O-word");
  }
}

// The items parsed up to `pos`, where a character no item starts with stands.
void BlockParser::report_stray_character(Block& out, const char* begin, const char* pos) {
  const char c = *pos;
  const int off = static_cast<int>(pos - begin);
  if (c == '[')
    add_error(out, ErrorCode::NumberWithoutLetter, off,
              "expression without a word letter in front");
  else if ((c >= '0' && c <= '9') || c == '.' || c == '+' || c == '-')
    add_error(out, ErrorCode::NumberWithoutLetter, off, "number without a word letter in front");
  else if (c == ')')
    add_error(out, ErrorCode::UnexpectedCharacter, off, "')' without a matching '('");
  else
    add_error(out, ErrorCode::UnexpectedCharacter, off, "unexpected character " + describe_char(c));
}

// A word or parameter setting failed: drops the unfinished item and whatever of its expression
// was emitted, reports why, and returns where to resume: after the brackets the item opened,
// so their contents make no further errors.
const char* BlockParser::drop_failed_item(Block& out, const char* begin, const char* end,
                                          const ItemFailure& fail) {
  char letter = '#';
  int item_pos = 0;
  if (ast_.open == ast::Open::Word) {
    letter = ast_.words[ast_.word_count - 1].letter;
    item_pos = ast_.words[ast_.word_count - 1].id_first;
    --ast_.word_count;
  } else {
    item_pos = ast_.assigns.back().pos;
    ast_.assigns.pop_back();
  }
  ast_.ops.resize(ast_.open_ops);
  ast_.open = ast::Open::None;
  int depth = 0;
  for (const char* q = begin + item_pos; q < fail.where; ++q) depth += (*q == '[') - (*q == ']');
  report_item_failure(out, begin, end, fail, letter, item_pos);
  const char* pos = fail.where;
  for (; pos != end && depth > 0; ++pos) depth -= (*pos == ']') - (*pos == '[');
  return pos;
}

// The message for a failed word (`letter`, written at `item_pos`) or parameter setting ('#').
void BlockParser::report_item_failure(Block& out, const char* begin, const char* end,
                                      const ItemFailure& fail, char letter, int item_pos) {
  const int off = static_cast<int>(fail.where - begin);
  const char at = fail.where == end ? '\0' : *fail.where;
  const std::string found = fail.where == end ? "" : ", found " + describe_char(at);
  switch (fail.code) {
    case ErrorCode::ExpectedNumber:
      if (letter == 'O') {
        add_error(out, ErrorCode::OWordsUnsupported, item_pos, "O-words are not supported");
      } else if (at >= 'A' && at <= 'Z') {
        // Letters then '[' name a function: say which name is unknown.
        const char* q = fail.where;
        while (q != end && *q >= 'A' && *q <= 'Z') ++q;
        if (q != end && *q == '[')
          add_error(out, ErrorCode::UnknownOperator, off,
                    "unknown function '" + std::string(fail.where, q) + "'");
        else
          add_error(out, ErrorCode::ExpectedNumber, off,
                    std::string("expected a number after '") + letter + "'" + found);
      } else
        add_error(out, ErrorCode::ExpectedNumber, off,
                  std::string("expected a number after '") + letter + "'" + found);
      break;
    case ErrorCode::UnclosedBracket:
      add_error(out, ErrorCode::UnclosedBracket, off,
                "expected ']' to close the expression" + found);
      break;
    case ErrorCode::UnknownOperator: {
      const char* q = fail.where;
      while (q != end && *q >= 'A' && *q <= 'Z') ++q;
      add_error(out, ErrorCode::UnknownOperator, off,
                "unknown function or operator '" + std::string(fail.where, q) + "'");
      break;
    }
    case ErrorCode::BadParameterName:
      add_error(out, ErrorCode::BadParameterName, off,
                at == '\0' || at != '>' ? "named parameter not closed: expected '>'"
                                        : "empty parameter name");
      break;
    case ErrorCode::ExpectedEquals:
      add_error(out, ErrorCode::ExpectedEquals, off,
                "expected '=' in the parameter setting" + found);
      break;
    default:
      add_error(out, ErrorCode::BadExpression, off,
                "expected a number, #parameter, [expression] or function" + found);
      break;
  }
}

// A comment failed (nested or not closed): drops it and reports why.
void BlockParser::drop_open_comment(Block& out, const char* begin, const ItemFailure& fail) {
  const int off = static_cast<int>(fail.where - begin);
  const int open_paren = ast_.comments[ast_.comment_count - 1].id_first;
  --ast_.comment_count;
  ast_.open = ast::Open::None;
  if (fail.code == ErrorCode::NestedComment)
    add_error(out, ErrorCode::NestedComment, off, "nested comment: '(' inside a comment");
  else
    add_error(out, ErrorCode::UnclosedComment, open_paren, "comment not closed: missing ')'");
}

// 3. Convert the expressions (one ExprOp per ast op, same indices), then the words; the errors
// in column order.
[[gnu::always_inline]] inline void BlockParser::convert(Block& out, const char* begin) {
  convert_expressions(out, begin);
  convert_words(out, begin);
  std::stable_sort(
      out.errors.begin(), out.errors.end(),
      [](const SyntaxError& a, const SyntaxError& b) { return a.loc.column < b.loc.column; });
}

[[gnu::always_inline]] inline void BlockParser::convert_expressions(Block& out, const char* begin) {
  for (const ast::ExprOp& a : ast_.ops) {
    ExprOp& op = out.ops.emplace_back();
    op.op = a.op;
    // A parameter is located at its '#': two characters before a name, one before a number.
    op.loc = loc_at(a.op == Op::Named ? a.first - 2 : a.op == Op::Param ? a.first - 1 : a.first);
    if (a.op == Op::Number) {
      const std::string_view num(begin + a.first, static_cast<std::size_t>(a.last - a.first));
      bool has_exponent = false;
      if (!to_double(num, op.value, has_exponent))
        add_error(out, ErrorCode::NumberOutOfRange, a.first,
                  "number out of range: " + show_number(num));
    } else if (a.op == Op::Named || a.op == Op::Exists) {
      add_name(out, begin, a.first, a.last, op.name, op.name_size);
    }
  }
  for (const ast::Block::Arg& a : ast_.args)
    out.oword.args.push_back(
        OpRange{static_cast<std::uint32_t>(a.first), static_cast<std::uint32_t>(a.last)});
  for (const ast::Assign& a : ast_.assigns) {
    Assignment& s = out.assignments.emplace_back();
    s.loc = loc_at(a.pos);
    s.named = a.name_first >= 0;
    if (s.named) add_name(out, begin, a.name_first, a.name_last, s.name, s.name_size);
    s.index = OpRange{static_cast<std::uint32_t>(a.index_first),
                      static_cast<std::uint32_t>(a.index_last)};
    s.value = OpRange{static_cast<std::uint32_t>(a.value_first),
                      static_cast<std::uint32_t>(a.value_last)};
  }
}

[[gnu::always_inline]] inline void BlockParser::convert_words(Block& out, const char* begin) {
  for (std::size_t i = 0; i < ast_.word_count; ++i) {
    const ast::Word& w = ast_.words[i];
    const SourceLoc loc = loc_at(w.id_first);
    if (w.letter == 'O') {
      add_error(out, ErrorCode::OWordsUnsupported, w.id_first, "O-words are not supported");
      continue;
    }
    if (w.expr_last > w.expr_first) {
      out.word_exprs.push_back(WordExpr{static_cast<std::uint32_t>(out.words.size()),
                                        OpRange{static_cast<std::uint32_t>(w.expr_first),
                                                static_cast<std::uint32_t>(w.expr_last)}});
      out.words.push_back(Word{w.letter, 0.0, loc});
      continue;
    }
    const std::string_view num(begin + w.num_first,
                               static_cast<std::size_t>(w.num_last - w.num_first));
    double value = 0.0;
    bool has_exponent = false;
    if (!to_double(num, value, has_exponent)) {
      add_error(out, ErrorCode::NumberOutOfRange, w.num_first,
                std::string("number out of range: ") + w.letter + show_number(num));
      continue;
    }
    if (has_exponent) {
      add_error(out, ErrorCode::ExponentUnsupported, w.num_first,
                std::string("exponent in ") + w.letter + show_number(num) +
                    ": G-code numbers have no exponent (E is a word letter)");
      continue;
    }
    out.words.push_back(Word{w.letter, value, loc, w.decimal_point});
  }
}

// 4. The active comment: LinuxCNC acts on the last comment of a line only. MSG, DEBUG, PRINT,
// ABORT, LOG, LOGOPEN, LOGAPPEND (each with a comma) and LOGCLOSE, in either case.
[[gnu::always_inline]] inline void BlockParser::active_comment(Block& out, const char* begin) {
  if (ast_.comment_count == 0) return;
  const ast::Comment& c = ast_.comments[ast_.comment_count - 1];
  std::string_view t(begin + c.text_first, static_cast<std::size_t>(c.text_last - c.text_first));
  if (macro_b_) out.remark.assign(t);
  while (!t.empty() && (t.front() == ' ' || t.front() == '\t')) t.remove_prefix(1);
  struct Keyword {
    std::string_view word;
    CommentKind kind;
    bool display;
  };
  static constexpr Keyword kKeywords[] = {
      {"MSG,", CommentKind::Msg, true},           {"DEBUG,", CommentKind::Debug, true},
      {"PRINT,", CommentKind::Print, true},       {"ABORT,", CommentKind::Abort, false},
      {"LOGOPEN,", CommentKind::LogOpen, false},  {"LOGAPPEND,", CommentKind::LogAppend, false},
      {"LOGCLOSE", CommentKind::LogClose, false}, {"LOG,", CommentKind::Log, false}};
  auto up = [](char ch) { return (ch >= 'a' && ch <= 'z') ? static_cast<char>(ch - 32) : ch; };
  for (const Keyword& k : kKeywords) {
    if (t.size() < k.word.size()) continue;
    bool match = true;
    for (std::size_t j = 0; j < k.word.size() && match; ++j) match = up(t[j]) == k.word[j];
    if (!match) continue;
    t.remove_prefix(k.word.size());
    while (!t.empty() && (t.front() == ' ' || t.front() == '\t')) t.remove_prefix(1);
    std::vector<Message>& list = k.display ? out.messages : out.directives;
    std::size_t& count = k.display ? out.message_count : out.directive_count;
    if (count == list.size()) list.emplace_back();
    Message& m = list[count++];
    m.text.assign(t);
    m.loc = loc_at(c.id_first);
    m.kind = k.kind;
    break;
  }
}

}  // namespace gm::grammar
