// The grammar facade: LinuxCNC spacing, numbers, comments, located syntax errors, robustness.
#include "grammar/parse.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>

using gm::ErrorCode;
using gm::grammar::Block;
using gm::grammar::BlockParser;

namespace {
Block parse(const std::string& text, int line = 1) {
  BlockParser p;
  Block b;
  p.parse(text, line, b);
  return b;
}
}  // namespace

TEST_CASE("spaces and tabs outside comments are insignificant (G 0 1 X 1 0 is G01 X10)") {
  const Block b = parse("G 0 1 X 1 0\t Y - 1 . 5");
  REQUIRE_FALSE(b.has_errors());
  REQUIRE(b.words.size() == 3);
  CHECK(b.words[0].letter == 'G');
  CHECK(b.words[0].value == 1.0);
  CHECK(b.words[0].loc.column == 1);
  CHECK(b.words[1].letter == 'X');
  CHECK(b.words[1].value == 10.0);
  CHECK(b.words[1].loc.column == 7);
  CHECK(b.words[2].value == -1.5);
  CHECK(b.words[2].loc.column == 14);
}

TEST_CASE("numbers: sign, leading and trailing point, either letter case") {
  const Block b = parse("x-.5 f600. y+2.25 z.125");
  REQUIRE_FALSE(b.has_errors());
  REQUIRE(b.words.size() == 4);
  CHECK(b.words[0].letter == 'X');
  CHECK(b.words[0].value == -0.5);
  CHECK(b.words[1].letter == 'F');
  CHECK(b.words[1].value == 600.0);
  CHECK(b.words[2].value == 2.25);
  CHECK(b.words[3].value == 0.125);
}

TEST_CASE("comments: parentheses, semicolon, MSG kept, CR LF") {
  Block b = parse("G1 (a comment) X1 ; rest G2 (ignored\r");
  REQUIRE_FALSE(b.has_errors());
  REQUIRE(b.words.size() == 2);
  CHECK(b.words[1].letter == 'X');
  CHECK(b.message_count == 0);
  b = parse("(MSG, Hello  World) G4 P1");
  REQUIRE_FALSE(b.has_errors());
  REQUIRE(b.message_count == 1);
  CHECK(b.messages[0].text == "Hello  World");
  CHECK(b.messages[0].loc.column == 1);
  CHECK(b.words.size() == 2);
  b = parse("( msg,lower case kept)");
  REQUIRE(b.message_count == 1);
  CHECK(b.messages[0].text == "lower case kept");
}

TEST_CASE("block delete, percent and empty lines") {
  Block b = parse("  / G0 X1");
  CHECK(b.block_delete);
  CHECK(b.words.size() == 2);
  b = parse("%");
  CHECK(b.percent);
  CHECK(b.words.empty());
  b = parse("   \t ");
  CHECK(b.words.empty());
  CHECK_FALSE(b.has_errors());
}

TEST_CASE("syntax errors carry code, line and column") {
  struct Case {
    const char* text;
    ErrorCode code;
    int column;
  };
  const Case cases[] = {
      {"G1 X", ErrorCode::ExpectedNumber, 5},
      {"G1 XY1", ErrorCode::ExpectedNumber, 5},
      {"XNaN", ErrorCode::ExpectedNumber, 2},
      {"G1 (a (b) c)", ErrorCode::NestedComment, 7},
      {"G1 (open", ErrorCode::UnclosedComment, 4},
      {"G1 X[1+2", ErrorCode::UnclosedBracket, 9},
      {"G1 X[1+]", ErrorCode::BadExpression, 8},
      {"G1 X[1 FOO 2]", ErrorCode::UnknownOperator, 8},
      {"G1 X[FIX 2]", ErrorCode::BadExpression, 10},
      {"G1 XFOO[2]", ErrorCode::UnknownOperator, 5},
      {"#1", ErrorCode::ExpectedEquals, 3},
      {"#<ab=2", ErrorCode::BadParameterName, 7},
      {"[1]", ErrorCode::NumberWithoutLetter, 1},
      {"o100 G0", ErrorCode::BadOWord, 6},  // bare "o100" is a Fanuc-style program start
      {"o100 bogus", ErrorCode::BadOWord, 6},
      {"N10 O<x call", ErrorCode::BadOWord, 6},
      {"o1 if [1+", ErrorCode::BadExpression, 10},
      {"o1 if [1", ErrorCode::UnclosedBracket, 9},
      {"o1 if [1] G0", ErrorCode::BadOWord, 11},
      {"G1 * X1", ErrorCode::UnexpectedCharacter, 4},
      {"G1 ) X1", ErrorCode::UnexpectedCharacter, 4},
      {"12 X1", ErrorCode::NumberWithoutLetter, 1},
  };
  {  // a number too large for a double (400 digits); E is a word letter, not an exponent
    const Block big = parse("X1" + std::string(400, '0'), 7);
    REQUIRE(big.errors.size() >= 1);
    CHECK(big.errors[0].code == ErrorCode::NumberOutOfRange);
    CHECK(big.errors[0].loc.column == 2);
    const Block e = parse("X1e3", 7);  // rs274: X1 then E3
    CHECK(e.errors.empty());
    REQUIRE(e.words.size() == 2);
    CHECK(e.words[1].letter == 'E');
    CHECK(e.words[1].value == 3.0);
  }
  for (const auto& c : cases) {
    INFO(c.text);
    const Block b = parse(c.text, 7);
    REQUIRE(b.errors.size() >= 1);
    CHECK(b.errors[0].code == c.code);
    CHECK(b.errors[0].loc.line == 7);
    CHECK(b.errors[0].loc.column == c.column);
  }
}

TEST_CASE("O-word lines: label, keyword and bracketed arguments") {
  Block b = parse("N5 o<My Sub> call [1+2] [#3] (comment)");
  REQUIRE_FALSE(b.has_errors());
  CHECK(b.oword.kind == gm::grammar::OKind::Call);
  CHECK(b.oword.named);
  CHECK(b.oword.label == "mysub");
  CHECK(b.oword.args.size() == 2);
  CHECK(b.oword.loc.column == 4);
  b = parse("O0100 ENDWHILE");
  REQUIRE_FALSE(b.has_errors());
  CHECK(b.oword.kind == gm::grammar::OKind::EndWhile);
  CHECK_FALSE(b.oword.named);
  CHECK(b.oword.label == "100");
  b = parse("G1 X1");
  CHECK(b.oword.kind == gm::grammar::OKind::None);
}

TEST_CASE("a number written out beyond double range is out of range, a tiny one is zero") {
  Block b = parse("X1" + std::string(400, '0'));
  REQUIRE(b.errors.size() == 1);
  CHECK(b.errors[0].code == ErrorCode::NumberOutOfRange);
  b = parse("X1" + std::string(100000, '0'));  // 10^5 digits
  REQUIRE(b.errors.size() == 1);
  CHECK(b.errors[0].code == ErrorCode::NumberOutOfRange);
  b = parse("X0." + std::string(400, '0') + "1");
  REQUIRE_FALSE(b.has_errors());
  CHECK(b.words[0].value == 0.0);
  b = parse("X1." + std::string(1000, '0'));
  REQUIRE_FALSE(b.has_errors());
  CHECK(b.words[0].value == 1.0);
}

TEST_CASE("every error of a line is reported, in column order") {
  const Block b = parse("G1 X Y2 Z# F[1+] (x (y)");
  REQUIRE(b.errors.size() == 4);
  CHECK(b.errors[0].code == ErrorCode::ExpectedNumber);
  CHECK(b.errors[0].loc.column == 6);                   // where the number should start
  CHECK(b.errors[1].code == ErrorCode::BadExpression);  // '#' without a number
  CHECK(b.errors[1].loc.column == 12);
  CHECK(b.errors[2].code == ErrorCode::BadExpression);  // '+' without its operand
  CHECK(b.errors[2].loc.column == 16);
  CHECK(b.errors[3].code == ErrorCode::NestedComment);
  CHECK(b.errors[3].loc.column == 21);
  // The good words survive (for the caller to ignore: a line with errors never runs).
  CHECK(b.words.size() == 2);
}

TEST_CASE("random bytes never crash, hang or produce unlocated errors") {
  const auto seed = std::random_device{}();
  CAPTURE(seed);
  std::mt19937 rng(seed);
  BlockParser p;
  Block b;
  for (int i = 0; i < 2000; ++i) {
    std::string s(static_cast<std::size_t>(rng() % 200), '\0');
    for (auto& ch : s) ch = static_cast<char>(rng() % 256);
    if (i % 2)
      for (auto& ch : s)
        if (ch == '\n') ch = ' ';
    CAPTURE(i);
    REQUIRE_NOTHROW(p.parse(s, i + 1, b));
    for (const auto& e : b.errors) {
      CHECK(e.code != ErrorCode::None);
      CHECK(e.loc.line == i + 1);
      CHECK(e.loc.column >= 1);
      CHECK(e.loc.column <= static_cast<int>(s.size()) + 1);
    }
    CHECK(b.errors.size() <= gm::grammar::kMaxErrorsPerLine);
  }
}

TEST_CASE("a megabyte line of letters is bounded to the per-line error cap") {
  const Block b = parse(std::string(1u << 20, 'X'));
  CHECK(b.errors.size() == gm::grammar::kMaxErrorsPerLine);
  CHECK(b.errors[0].code == ErrorCode::ExpectedNumber);
}

TEST_CASE("number conversion equals std::from_chars (fast decimal path and general path)") {
  // The parser converts plain decimals with <= 15 significant digits by one exact division
  // (mantissa / 10^decimals); every other number goes through from_chars. Both must give the
  // correctly rounded double.
  const std::uint64_t seed = 31337;
  std::mt19937_64 rng(seed);
  CAPTURE(seed);
  for (int i = 0; i < 100000; ++i) {
    const int int_digits = static_cast<int>(rng() % 12);
    const int frac_digits = static_cast<int>(rng() % 25);
    std::string num;
    for (int d = 0; d < int_digits; ++d) num += static_cast<char>('0' + rng() % 10);
    if (frac_digits > 0 || num.empty()) {
      num += '.';
      for (int d = 0; d < std::max(frac_digits, num.size() == 1 ? 1 : 0); ++d)
        num += static_cast<char>('0' + rng() % 10);
    }
    const bool negative = rng() % 2 == 0;
    const Block b = parse(std::string("X") + (negative ? "-" : "") + num);
    INFO(num);
    REQUIRE(b.errors.empty());
    REQUIRE(b.words.size() == 1);
    double expect = 0;
    std::from_chars(num.data(), num.data() + num.size(), expect);
    if (negative) expect = -expect;
    REQUIRE(b.words[0].value == expect);
    REQUIRE(std::signbit(b.words[0].value) == std::signbit(expect));
  }
}
