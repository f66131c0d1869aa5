// Fast paths of the block rule: a line of only letters and plain decimal numbers, read from the
// line itself or from its compacted form.
#pragma once

#include "grammar/decimal_scan.hpp"
#include "grammar/parse.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace gm::grammar {

/// Reads `compact` from `start` when it holds nothing but words of a letter (A-Z but O) and a
/// plain number ([+-] digits [. digits], or [+-] . digits) with at most 15 digits after the
/// leading zeros, appending them to `words` with the values and locations the block rule and
/// the number conversion give (`columns`: the source column of each compact character). False
/// at anything else (a comment, an expression, a parameter, an O, a long number, a stray
/// character): `words` then holds a partial result and the line takes the general path.
/// Exact: the mantissa (< 10^15) and 10^decimals (decimals <= 15) are exact doubles, so the one
/// division is correctly rounded, as std::from_chars is (tests/grammar/test_plain_words.cpp
/// compares both paths line by line).
inline bool read_plain_words(std::string_view compact, std::size_t start, const int* columns,
                             int line, std::vector<Word>& words) {
  const char* const begin = compact.data();
  const char* const end = begin + compact.size();
  const char* p = begin + start;
  while (p != end) {
    const char letter = *p;
    if (static_cast<unsigned>(letter - 'A') >= 26u || letter == 'O') return false;
    const int at = static_cast<int>(p - begin);
    ++p;
    bool negative = false;
    if (p != end && (*p == '-' || *p == '+')) negative = *p++ == '-';
    const DecimalScan d = scan_decimal(p, end);
    double v = 0.0;
    if (!exact_decimal(d, v)) return false;  // no digit ('X', 'X-', 'X.'), or too many
    words.emplace_back(letter, negative ? -v : v, SourceLoc{line, columns[at]}, d.point);
  }
  return true;
}

/// read_plain_words's words read from the line itself, without compacting it first: `text` (one
/// line, its '\r' dropped) holds only words of a letter (A-Z, a-z, but O) and a plain number,
/// with blanks (' ', '\t') only between words and between a letter and its number. The columns
/// are the letters' own. True with the words the compacting path gives; false at anything else,
/// which that path then reads (a blank inside a number, a comment, an expression, a '/' or '%'
/// opening the line, a long number, an M98/M99 first on the line or after its N: control flow):
/// `words` then holds a partial result. kDecimalReadAhead bytes past the text must be readable.
inline bool read_plain_line(std::string_view text, int line, std::vector<Word>& words) {
  const char* const begin = text.data();
  const char* const end = begin + text.size();
  const char* p = begin;
  const auto blank = [](char c) { return c == ' ' || c == '\t'; };
  while (p != end) {
    char letter = *p;
    if (blank(letter)) {
      ++p;
      continue;
    }
    if (static_cast<unsigned char>(letter - 'a') < 26u)
      letter = static_cast<char>(letter - 'a' + 'A');
    if (static_cast<unsigned char>(letter - 'A') >= 26u || letter == 'O') return false;
    const int column = static_cast<int>(p - begin) + 1;
    ++p;
    while (p != end && blank(*p)) ++p;
    bool negative = false;
    if (p != end && (*p == '-' || *p == '+')) negative = *p++ == '-';
    double v = 0.0;
    bool point = false;
    const char* const number = p;
    if (!read_short_decimal(p, v, point) || p > end) {  // (past the end: the padding's digits)
      p = number;
      const DecimalScan d = scan_decimal(p, end);
      if (!exact_decimal(d, v)) return false;  // no digit, too many, or a blank after the sign
      point = d.point;
    }
    words.emplace_back(letter, negative ? -v : v, SourceLoc{line, column}, point);
  }
  // The block rule reads M98 and M99 opening the line (after an optional N) as control flow.
  const auto flow = [](const Word& w) {
    return w.letter == 'M' && (w.value == 98.0 || w.value == 99.0);
  };
  const std::size_t n = words.size();
  return !(n > 0 && (flow(words[0]) || (n > 1 && words[0].letter == 'N' && flow(words[1]))));
}

}  // namespace gm::grammar
