// Fast path of the block rule: a compacted line of only letters and plain decimal numbers.
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

}  // namespace gm::grammar
