// Plain decimal numbers (digits [. digits]) read into an exact integer mantissa: the fast path of
// the number conversion, shared by the block rule's conversion and the plain-line scanner.
#pragma once

#include <cstddef>
#include <cstdint>

namespace gm::grammar {

/// What scan_decimal read.
struct DecimalScan {
  std::uint64_t mantissa = 0;      ///< the digits after the leading zeros, as one integer
  std::ptrdiff_t significant = 0;  ///< how many digits that is (integer part and fraction)
  std::ptrdiff_t decimals = 0;     ///< digits after the point
  bool any_digit = false;          ///< a digit at all (a leading zero counts): not "", "."
  bool point = false;              ///< a decimal point was read ("2.", ".5", "2.5")
};

/// Reads digits [. digits] at `p` (left after them; nothing else is consumed).
inline DecimalScan scan_decimal(const char*& p, const char* end) {
  auto digit = [](char c) { return static_cast<unsigned>(c - '0') < 10u; };
  DecimalScan s;
  const char* const first = p;
  while (p != end && *p == '0') ++p;  // leading zeros are not significant
  const char* const int_start = p;
  for (; p != end && digit(*p); ++p) s.mantissa = s.mantissa * 10 + static_cast<unsigned>(*p - '0');
  s.significant = p - int_start;
  s.any_digit = p != first;
  if (p != end && *p == '.') {
    s.point = true;
    const char* const frac_start = ++p;
    for (; p != end && digit(*p); ++p)
      s.mantissa = s.mantissa * 10 + static_cast<unsigned>(*p - '0');
    s.decimals = p - frac_start;
    s.significant += s.decimals;
    s.any_digit = s.any_digit || s.decimals > 0;
  }
  return s;
}

/// The value of `s` when one division gives it exactly rounded: at most 15 significant digits,
/// so the mantissa (< 10^15) and 10^decimals are exact doubles and the quotient is what
/// std::from_chars gives (Clinger's fast path). False: no digit, or too many (the mantissa may
/// have wrapped): take the general path.
inline bool exact_decimal(const DecimalScan& s, double& value) {
  static constexpr double kPow10[] = {1e0, 1e1, 1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                      1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15};
  if (!s.any_digit || s.significant > 15) return false;
  value = static_cast<double>(s.mantissa) / kPow10[s.decimals];
  return true;
}

}  // namespace gm::grammar
