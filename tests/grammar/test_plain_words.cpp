// The plain-line scanner against the block rule: hand-worked lines, then every bundled program,
// test program, fuzz regression and a random set parsed both ways, compared field by field.
#include "grammar/compact_line.hpp"
#include "grammar/parse.hpp"
#include "grammar/plain_words.hpp"
#include "support/read_file.hpp"
#include "support/test_scale.hpp"

#include <catch2/catch.hpp>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <string_view>
#include <vector>

using gm::grammar::Block;
using gm::grammar::BlockParser;
using gm::grammar::Word;

namespace {

/// The scanner alone on a line as compact_plain_line gives it (no comment in `text`).
bool scan(std::string_view text, std::vector<Word>& words) {
  std::string compact(text.size() + gm::grammar::kCompactSlack, '\0');
  std::vector<int> columns(text.size() + 1 + gm::grammar::kCompactSlack);
  char* cp = compact.data();
  int* colp = columns.data();
  gm::grammar::compact_plain_line(text, cp, colp);
  words.clear();
  return gm::grammar::read_plain_words(
      std::string_view(compact.data(), static_cast<std::size_t>(cp - compact.data())), 0,
      columns.data(), 7, words);
}

/// The scanner of uncompacted lines (the text with room to read ahead, digits there).
bool scan_line(std::string_view text, std::vector<Word>& words) {
  std::string padded(text);
  padded.append(gm::grammar::kDecimalReadAhead, '5');
  words.clear();
  return gm::grammar::read_plain_line(std::string_view(padded.data(), text.size()), 7, words);
}

std::string describe(const Block& b) {
  std::string s = "line " + std::to_string(b.line) + (b.block_delete ? " /" : "") +
                  (b.percent ? " %" : "") + (b.percent_text ? " %text" : "") + "\n";
  for (const auto& w : b.words)
    s += std::string(1, w.letter) + (w.decimal_point ? "." : "") + " " +
         std::to_string(std::bit_cast<std::uint64_t>(w.value)) + " @" + std::to_string(w.loc.line) +
         ":" + std::to_string(w.loc.column) + "\n";
  for (const auto& e : b.errors)
    s += "error " + std::to_string(static_cast<int>(e.code)) + " @" + std::to_string(e.loc.column) +
         " " + e.message + "\n";
  for (std::size_t i = 0; i < b.message_count; ++i)
    s += "message " + std::to_string(static_cast<int>(b.messages[i].kind)) + " " +
         b.messages[i].text + " @" + std::to_string(b.messages[i].loc.column) + "\n";
  for (std::size_t i = 0; i < b.directive_count; ++i)
    s += "directive " + std::to_string(static_cast<int>(b.directives[i].kind)) + " " +
         b.directives[i].text + "\n";
  for (const auto& op : b.ops)
    s += "op " + std::to_string(static_cast<int>(op.op)) + " " +
         std::to_string(std::bit_cast<std::uint64_t>(op.value)) + " " + std::to_string(op.name) +
         "+" + std::to_string(op.name_size) + " @" + std::to_string(op.loc.column) + "\n";
  for (const auto& x : b.word_exprs)
    s += "expr " + std::to_string(x.word) + " " + std::to_string(x.ops.first) + ".." +
         std::to_string(x.ops.last) + "\n";
  for (const auto& a : b.assignments)
    s += "assign @" + std::to_string(a.loc.column) + (a.named ? " named " : " ") +
         std::to_string(a.name) + "+" + std::to_string(a.name_size) + " " +
         std::to_string(a.index.first) + ".." + std::to_string(a.index.last) + " " +
         std::to_string(a.value.first) + ".." + std::to_string(a.value.last) + "\n";
  s += "names " + b.names + "\n";
  s += "oword " + std::to_string(static_cast<int>(b.oword.kind)) + " " + b.oword.label + " " +
       std::to_string(b.oword.loc.column) + " " + std::to_string(b.oword.args.size()) + "\n";
  s += "sequence " + std::to_string(b.sequence) + " remark " + b.remark + "\n";
  return s;
}

/// Parses every line of `text` with the scanner on and off (the parsers and blocks kept from
/// line to line, as the reader keeps them) and requires the same blocks. Returns the lines.
std::size_t compare_lines(std::string_view text, bool macro_b) {
  BlockParser fast, rule;
  fast.set_macro_b(macro_b);
  rule.set_macro_b(macro_b);
  rule.set_plain_fast_path(false);
  Block a, b;
  std::size_t n = 0;
  while (!text.empty()) {
    const std::size_t nl = text.find('\n');
    const std::string_view line = text.substr(0, nl);
    text = nl == std::string_view::npos ? std::string_view() : text.substr(nl + 1);
    ++n;
    fast.parse(line, static_cast<int>(n), a);
    rule.parse(line, static_cast<int>(n), b);
    const std::string da = describe(a), db = describe(b);
    if (da != db) {
      INFO("line " << n << ": " << line);
      CHECK(da == db);
    }
  }
  return n;
}

}  // namespace

TEST_CASE("plain-line scanner: hand-worked lines") {
  std::vector<Word> w;
  REQUIRE(scan("G1 x-.5 Y10.25 f600.", w));
  REQUIRE(w.size() == 4);
  CHECK(w[0].letter == 'G');
  CHECK(w[0].value == 1.0);
  CHECK(w[0].loc.column == 1);
  CHECK(w[0].loc.line == 7);
  CHECK(w[1].letter == 'X');
  CHECK(w[1].value == -0.5);
  CHECK(w[1].loc.column == 4);
  CHECK(w[2].value == 10.25);
  CHECK(w[2].loc.column == 9);
  CHECK(w[3].letter == 'F');
  CHECK(w[3].value == 600.0);
  CHECK(w[3].loc.column == 16);

  // The decimal point is kept: `F600.` and `X-.5` have one, `G1` not.
  CHECK_FALSE(w[0].decimal_point);
  CHECK(w[1].decimal_point);
  CHECK(w[2].decimal_point);
  CHECK(w[3].decimal_point);
  REQUIRE(scan("G4 P2000 X2. P0", w));
  REQUIRE(w.size() == 4);
  CHECK_FALSE(w[1].decimal_point);
  CHECK(w[2].decimal_point);
  CHECK_FALSE(w[3].decimal_point);

  REQUIRE(scan("X 1 0\tY+007.50 Z-0", w));  // spaces inside a number, leading zeros, -0
  REQUIRE(w.size() == 3);
  CHECK(w[0].value == 10.0);
  CHECK(w[1].value == 7.5);
  CHECK(w[1].loc.column == 7);
  CHECK(w[2].value == 0.0);
  CHECK(std::signbit(w[2].value));

  // 0.1 is not 1/10 computed in steps: the one division gives the nearest double, 0x3FB999...9A.
  REQUIRE(scan("X0.1 Y123456789.012345", w));
  CHECK(std::bit_cast<std::uint64_t>(w[0].value) == 0x3FB999999999999AULL);
  CHECK(w[1].value == 123456789.012345);

  REQUIRE(scan("", w));
  CHECK(w.empty());
  // What the scanner leaves to the block rule.
  for (const char* line : {"G1 X[1+2]", "G1 X#1", "#1=2", "G1 (c)", "O100 sub", "G1 X1 O2", "X",
                           "X-", "X.", "X-.", "X1.2.3", "X+-1", "X1**2", "@5 ^90", "X1 *",
                           "X1234567890123456", "X0.0000000000000001", "N10 G1 X1 %", "G1 X1é"})
    CHECK_FALSE(scan(line, w));
  // 15 digits after the leading zeros still fit; leading zeros do not count.
  CHECK(scan("X123456789012345 Y0000000000000000001.5", w));
}

TEST_CASE("plain-line scanner on the line itself: hand-worked lines") {
  std::vector<Word> w;
  REQUIRE(scan_line("G1 x-.5 Y10.25\tf600.", w));
  REQUIRE(w.size() == 4);
  CHECK(w[0].letter == 'G');
  CHECK(w[0].value == 1.0);
  CHECK_FALSE(w[0].decimal_point);
  CHECK(w[0].loc.line == 7);
  CHECK(w[0].loc.column == 1);
  CHECK(w[1].letter == 'X');
  CHECK(w[1].value == -0.5);
  CHECK(w[1].decimal_point);
  CHECK(w[1].loc.column == 4);
  CHECK(w[2].value == 10.25);
  CHECK(w[2].loc.column == 9);
  CHECK(w[3].letter == 'F');
  CHECK(w[3].value == 600.0);
  CHECK(w[3].decimal_point);
  CHECK(w[3].loc.column == 16);

  // Blanks between a letter and its number, and around words, are passed over.
  REQUIRE(scan_line("  X 10\tY\t+007.50 Z -0 ", w));
  REQUIRE(w.size() == 3);
  CHECK(w[0].value == 10.0);
  CHECK(w[0].loc.column == 3);
  CHECK(w[1].value == 7.5);
  CHECK(w[1].loc.column == 8);
  CHECK(w[2].value == 0.0);
  CHECK(std::signbit(w[2].value));
  CHECK(w[2].loc.column == 18);
  REQUIRE(scan_line("X0.1", w));
  CHECK(std::bit_cast<std::uint64_t>(w[0].value) == 0x3FB999999999999AULL);
  REQUIRE(scan_line(" \t ", w));
  CHECK(w.empty());
  // M98/M99 with a number other than 98 or 99, or not opening the line, are plain words.
  CHECK(scan_line("M9 M8", w));
  CHECK(scan_line("G1 M98", w));
  CHECK(scan_line("N1 G0 M99", w));

  // What it leaves to the compacting path: blanks inside a number, a sign apart from its
  // digits, control flow, and everything read_plain_words leaves to the block rule.
  for (const char* line : {"X1 0", "X- 1", "X1. 5", "X1 .5", "X1 -2", "M98 P1", "m099", "N10 M99",
                           "/G1 X1", "%", "G1 X1 O2", "G1 (c)", "G1 X1 ;c", "G1 X[1]", "X",
                           "X1234567890123456", "G1 X1\r", "G1 X1\v", "G1 X1\xc3\xa9"}) {
    INFO(line);
    CHECK_FALSE(scan_line(line, w));
  }
}

TEST_CASE("short numbers read 8 bytes at a time: scan_decimal's values, points and ends") {
  // Every number of up to 8 digits on each side of a point (and none), with what may follow.
  std::mt19937 rng(99);
  std::uniform_int_distribution<int> digit(0, 9), count(0, 9), tail(0, 5);
  int short_ones = 0;
  for (int i = 0; i < 200000; ++i) {
    std::string s;
    const int n1 = count(rng), n2 = count(rng);
    for (int k = 0; k < n1; ++k) s += static_cast<char>('0' + digit(rng));
    if (i % 3 != 0) {
      s += '.';
      for (int k = 0; k < n2; ++k) s += static_cast<char>('0' + digit(rng));
    }
    s += " X.1-/"[tail(rng)];
    s.append(gm::grammar::kDecimalReadAhead, '\0');
    const char* p = s.data();
    double v = 0.0;
    bool point = false;
    if (!gm::grammar::read_short_decimal(p, v, point)) continue;
    ++short_ones;
    const char* q = s.data();
    const gm::grammar::DecimalScan d = gm::grammar::scan_decimal(q, s.data() + s.size());
    double want = 0.0;
    INFO(s);
    REQUIRE(gm::grammar::exact_decimal(d, want));
    REQUIRE(std::bit_cast<std::uint64_t>(v) == std::bit_cast<std::uint64_t>(want));
    REQUIRE(point == d.point);
    REQUIRE(p == q);
  }
  CHECK(short_ones > 100000);
  const char* p = "12345678.5\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0";  // 8 digits: left to scan_decimal
  double v = 0.0;
  bool point = false;
  CHECK_FALSE(gm::grammar::read_short_decimal(p, v, point));
  p = "1234567.7654321 \0\0\0\0\0\0\0\0\0\0\0\0\0\0\0";
  REQUIRE(gm::grammar::read_short_decimal(p, v, point));
  CHECK(v == 1234567.7654321);
  CHECK(point);
  CHECK(*p == ' ');
}

TEST_CASE("decimal point: the scanner and the block rule keep it alike") {
  BlockParser fast, rule;
  rule.set_plain_fast_path(false);
  Block a, b;
  // Plain lines (the scanner on `fast`), then lines only the block rule reads.
  for (const char* line : {"G04 P2000 X2. Y.5 Z-1.25 F0", "G4 P200 (dwell)", "G1 X[2.5] Y#1 Z3.",
                           "G1 X1.E5", "#1=2. G4 P2"}) {
    INFO(line);
    fast.parse(line, 1, a);
    rule.parse(line, 1, b);
    CHECK(describe(a) == describe(b));
  }
  fast.parse("G04 P2000 X2. Y.5 Z-1.25 F0", 1, a);
  REQUIRE(a.words.size() == 6);
  const bool want[] = {false, false, true, true, true, false};
  for (std::size_t i = 0; i < 6; ++i) CHECK(a.words[i].decimal_point == want[i]);
  rule.parse("G4 P200 (dwell)", 1, b);
  REQUIRE(b.words.size() == 2);
  CHECK_FALSE(b.words[1].decimal_point);
  // An expression's value has no written point; `Z3.` after it has.
  rule.parse("G1 X[2.5] Y#1 Z3.", 1, b);
  REQUIRE(b.words.size() == 4);
  CHECK_FALSE(b.words[1].decimal_point);
  CHECK_FALSE(b.words[2].decimal_point);
  CHECK(b.words[3].decimal_point);
  // The word storage is reused from line to line: a point does not stay behind.
  rule.parse("X1. Y2. Z3.", 1, b);
  rule.parse("X1 Y2 Z[3.]", 1, b);
  REQUIRE(b.words.size() == 3);
  for (const auto& w : b.words) CHECK_FALSE(w.decimal_point);
}

TEST_CASE("plain-line scanner: the same blocks as the block rule on every program") {
  namespace fs = std::filesystem;
  const fs::path tests(GMOTION_TESTS_DIR);
  std::size_t files = 0, lines = 0;
  for (const fs::path& root : {tests, tests / ".." / "programs"}) {
    for (const auto& e : fs::recursive_directory_iterator(root)) {
      if (!e.is_regular_file()) continue;
      const std::string ext = e.path().extension().string();
      const bool fuzz_case = e.path().string().find("regressions") != std::string::npos;
      if (ext != ".nc" && ext != ".ngc" && !fuzz_case) continue;
      if (e.file_size() > (std::uintmax_t{1} << 20)) continue;
      const std::string text = gmtest::slurp(e.path());
      INFO(e.path().string());
      lines += compare_lines(text, false);
      lines += compare_lines(text, true);
      ++files;
    }
  }
  CHECK(files > 250);
  CHECK(lines > 6000);
}

TEST_CASE("plain-line scanner: the same blocks as the block rule on random lines") {
  // Pieces of ordinary lines and of everything the scanner must leave alone.
  static const char* const kPieces[] = {"G",    "X",     "Y",
                                        "Z",    "I",     "J",
                                        "F",    "M",     "N",
                                        "O",    "E",     "e",
                                        "x",    "@",     "^",
                                        "1",    "0",     "7",
                                        "9",    "5",     "2",
                                        ".",    "-",     "+",
                                        " ",    "\t",    "(",
                                        ")",    ";",     "#",
                                        "[",    "]",     "*",
                                        "/",    "=",     "<",
                                        ">",    "%",     "\r",
                                        "00",   "12",    "3.5",
                                        "-.25", "1.",    "MOD",
                                        "G1",   "X-1.5", " Y2.25",
                                        " Z0",  "F600",  "1234567890123456",
                                        "\x80", "SIN[",  "MSG,",
                                        "R",    "98",    "M99",
                                        "N1",   " 0",    "m"};
  std::mt19937 rng(12345);
  std::uniform_int_distribution<std::size_t> piece(0, std::size(kPieces) - 1);
  std::uniform_int_distribution<int> length(0, 14);
  std::string text;
  const auto lines = static_cast<std::size_t>(gmtest::scaled(60000));
  for (std::size_t i = 0; i < lines; ++i) {
    const int n = length(rng);
    for (int k = 0; k < n; ++k) text += kPieces[piece(rng)];
    text += '\n';
  }
  CHECK(compare_lines(text, false) == lines);
  CHECK(compare_lines(text, true) == lines);

  // Plain lines, as CAM writes them: the scanner takes all of them.
  std::uniform_int_distribution<int> digits(0, 99999999);
  std::string plain;
  std::vector<Word> w;
  std::size_t taken = 0;
  for (int i = 0; i < 20000; ++i) {
    std::string line = "G" + std::to_string(i % 4);
    for (const char* axis : {" X", " Y", " Z", " I", " J"}) {
      const int d = digits(rng);
      line += axis;
      if (d % 3 == 0) line += '-';
      line += std::to_string(d / 10000) + "." + std::to_string(d % 10000);
    }
    taken += scan(line, w) ? 1 : 0;
    plain += line + "\n";
  }
  CHECK(taken == 20000);
  CHECK(compare_lines(plain, false) == 20000);
}
