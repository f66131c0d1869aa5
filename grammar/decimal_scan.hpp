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

/// Bytes past a number's text that read_short_decimal may read (they need not be the line's).
inline constexpr std::size_t kDecimalReadAhead = 16;

namespace detail {

/// How many of the 8 bytes of `x` (in memory order) are decimal digits before the first other.
inline int digit_run(std::uint64_t x) {
  // A digit byte 0x30..0x39 has high nibble 3, and so has the byte plus 6; any other byte
  // differs in one of them (a carry out of a byte comes only from a byte past the run).
  const std::uint64_t other =
      ((x & 0xF0F0F0F0F0F0F0F0ull) | (((x + 0x0606060606060606ull) & 0xF0F0F0F0F0F0F0F0ull) >> 4)) ^
      0x3333333333333333ull;
  return other == 0 ? 8 : __builtin_ctzll(other) / 8;
}

/// The value of the first `n` (0..7) digit bytes of `x` (in memory order, most significant
/// first): the digits moved up to the top bytes, the bytes below read as leading zeros.
inline std::uint64_t digits_value(std::uint64_t x, int n) {
  if (n == 0) return 0;
  x = (x & 0x0F0F0F0F0F0F0F0Full) << (8 * (8 - n));
  x = (x * 10 + (x >> 8)) & 0x00FF00FF00FF00FFull;
  x = (x * 100 + (x >> 16)) & 0x0000FFFF0000FFFFull;
  return (x * 10000 + (x >> 32)) & 0xFFFFFFFFull;
}

}  // namespace detail

/// scan_decimal and exact_decimal at once for the common short number: digits [. digits] with at
/// most 7 digits on each side of the point, read 8 bytes at a time (kDecimalReadAhead bytes from
/// `p` must be readable). True with `p` after the number, `value` and `point` as those give them;
/// false (nothing consumed) for anything else, which they then read.
inline bool read_short_decimal(const char*& p, double& value, bool& point) {
  static constexpr double kPow10[] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7};
  static constexpr std::uint64_t kScale[] = {1, 10, 100, 1000, 10000, 100000, 1000000, 10000000};
  std::uint64_t a = 0;
  __builtin_memcpy(&a, p, 8);
  const int n1 = detail::digit_run(a);
  if (n1 == 8) return false;
  if (p[n1] != '.') {
    if (n1 == 0) return false;
    value = static_cast<double>(detail::digits_value(a, n1));
    point = false;
    p += n1;
    return true;
  }
  std::uint64_t b = 0;
  __builtin_memcpy(&b, p + n1 + 1, 8);
  const int n2 = detail::digit_run(b);
  if (n2 == 8 || n1 + n2 == 0) return false;
  const std::uint64_t mantissa =
      detail::digits_value(a, n1) * kScale[n2] + detail::digits_value(b, n2);
  value = static_cast<double>(mantissa) / kPow10[n2];
  point = true;
  p += n1 + 1 + n2;
  return true;
}

}  // namespace gm::grammar
