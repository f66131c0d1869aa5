// Fast path of the block rule: a compacted line of only letters and plain decimal numbers.
#pragma once

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
  static constexpr double kPow10[] = {1e0, 1e1, 1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                      1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15};
  const char* const begin = compact.data();
  const char* const end = begin + compact.size();
  const char* p = begin + start;
  auto digit = [](char c) { return static_cast<unsigned>(c - '0') < 10u; };
  while (p != end) {
    const char letter = *p;
    if (static_cast<unsigned>(letter - 'A') >= 26u || letter == 'O') return false;
    const int at = static_cast<int>(p - begin);
    ++p;
    bool negative = false;
    if (p != end && (*p == '-' || *p == '+')) negative = *p++ == '-';
    const char* const num_start = p;
    while (p != end && *p == '0') ++p;  // leading zeros are not significant
    const char* const int_start = p;
    std::uint64_t mantissa = 0;
    for (; p != end && digit(*p); ++p)
      mantissa = mantissa * 10 + static_cast<std::uint64_t>(*p - '0');
    std::ptrdiff_t digits = p - int_start;
    const bool any_int = p != num_start;
    std::ptrdiff_t decimals = 0;
    if (p != end && *p == '.') {
      const char* const frac_start = ++p;
      for (; p != end && digit(*p); ++p)
        mantissa = mantissa * 10 + static_cast<std::uint64_t>(*p - '0');
      decimals = p - frac_start;
      digits += decimals;
    }
    // No digit at all ('X', 'X-', 'X.'), or too many for the exact division.
    if ((!any_int && decimals == 0) || digits > 15) return false;
    const double v = static_cast<double>(mantissa) / kPow10[decimals];
    words.push_back(Word{letter, negative ? -v : v, SourceLoc{line, columns[at]}});
  }
  return true;
}

}  // namespace gm::grammar
