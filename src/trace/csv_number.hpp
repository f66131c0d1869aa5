// Number formatting for the CSV trace: the exact text fmt's "{}" and "{:.Nf}" give, faster.
#pragma once

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace gm {

namespace csv_detail {

/// "00" "01" ... "99": two digits a lookup, as fmt and every fast formatter do.
inline constexpr char kDigitPairs[] =
    "0001020304050607080910111213141516171819202122232425262728293031323334353637383940414243444546"
    "4748495051525354555657585960616263646566676869707172737475767778798081828384858687888990919293"
    "949596979899";

inline void put_pair(char* q, unsigned r) {
  std::memcpy(q, kDigitPairs + 2 * r, 2);
}
/// Decimal digits of v (1..20).
inline int count_digits(std::uint64_t v) {
  static constexpr std::uint64_t kPow10[20] = {1u,
                                               10u,
                                               100u,
                                               1000u,
                                               10000u,
                                               100000u,
                                               1000000u,
                                               10000000u,
                                               100000000u,
                                               1000000000u,
                                               10000000000u,
                                               100000000000u,
                                               1000000000000u,
                                               10000000000000u,
                                               100000000000000u,
                                               1000000000000000u,
                                               10000000000000000u,
                                               100000000000000000u,
                                               1000000000000000000u,
                                               10000000000000000000u};
  // floor(log10(2^bit_width)) by 1233/4096 ≈ log10(2), then one comparison corrects it.
  const int t = ((64 - __builtin_clzll(v | 1)) * 1233) >> 12;
  return v == 0 ? 1 : t - static_cast<int>(v < kPow10[t]) + 1;
}

/// The four decimal digits of every value below 10^4, one digit value (0..9) a byte, the first
/// digit in the lowest byte: 40 KB, of which a trace's slowly changing columns touch a few lines.
inline constexpr auto kDigitQuads = [] {
  std::array<std::uint32_t, 10000> t{};
  for (std::uint32_t v = 0; v < 10000; ++v)
    t[v] = v / 1000 | (v / 100 % 10) << 8 | (v / 10 % 10) << 16 | (v % 10) << 24;
  return t;
}();

/// The eight decimal digits of v (< 10^8) as one word, one digit value (0..9) a byte, the most
/// significant digit in the lowest byte (memory order on little-endian machines): two lookups,
/// no branch.
[[gnu::always_inline]] inline std::uint64_t digit_bytes8(std::uint32_t v) {
  const std::uint32_t hi = v / 10000, lo = v - hi * 10000;
  return kDigitQuads[hi] | static_cast<std::uint64_t>(kDigitQuads[lo]) << 32;
}

static_assert(std::endian::native == std::endian::little,
              "the digit words are stored as they are: first digit in the lowest byte");

/// The digit bytes of digit_bytes8 as ASCII, in memory order.
[[gnu::always_inline]] inline void store_digits8(char* p, std::uint64_t digits) {
  const std::uint64_t w = digits + 0x3030303030303030ull;
  std::memcpy(p, &w, 8);
}

/// Writes v (< 10^8) without leading zeros as one 8-byte store (p needs 8 bytes of room);
/// returns the end. The leading zero digits are the zero bytes at the low end of the word.
[[gnu::always_inline]] inline char* put_uint8(char* p, std::uint32_t v) {
  const std::uint64_t digits = digit_bytes8(v);
  // At most seven leading zeros: 0 is written as "0".
  const int zeros = __builtin_ctzll(digits | 1ull << 56) >> 3;
  store_digits8(p, digits >> (8 * zeros));
  return p + 8 - zeros;
}

/// put_uint for v >= 10^8 (out of line: a trace's counts are smaller).
char* put_uint_long(char* p, std::uint64_t v);

/// Writes v in decimal at p, straight into place; returns the end. Below 10^8 (every count a
/// trace holds in practice) one branch-free conversion, inlined (put_uint8); p must have 8
/// bytes of room past the end of the text.
[[gnu::always_inline]] inline char* put_uint(char* p, std::uint64_t v) {
  if (v < 10) {  // zeros (idle axes, following errors at rest) are common: one digit
    *p = static_cast<char>('0' + v);
    return p + 1;
  }
  if (v < 100000000u) [[likely]]
    return put_uint8(p, static_cast<std::uint32_t>(v));
  return put_uint_long(p, v);
}

/// Writes exactly D digits of f (< 10^D) at p, leading zeros kept; returns the end.
/// (D <= 8: the last D digits of one digit_bytes8 word, as one 8-byte store.)
template <int D>
[[gnu::always_inline]] inline char* put_fraction(char* p, std::uint64_t f) {
  if constexpr (D <= 8) {
    store_digits8(p, digit_bytes8(static_cast<std::uint32_t>(f)) >> (8 * (8 - D)));
    return p + D;
  }
  char* q = p + D;
  for (int d = D; d >= 2; d -= 2) {
    const auto r = static_cast<unsigned>(f % 100);
    f /= 100;
    q -= 2;
    put_pair(q, r);
  }
  if constexpr (D % 2 == 1) q[-1] = static_cast<char>('0' + f);
  return p + D;
}

/// fmt's "{:.Nf}" for every x (the general path of put_fixed).
char* put_fixed_fmt(char* p, double x, int decimals);

}  // namespace csv_detail

/// Writes `v` in decimal at `p` (at most 20 characters; p needs 21 bytes of room); returns the
/// end. Same text as "{}".
[[gnu::always_inline]] inline char* put_int(char* p, std::int64_t v) {
  // Without a branch: following errors change sign unpredictably.
  const auto u = static_cast<std::uint64_t>(v);
  *p = '-';
  p += v < 0;
  return csv_detail::put_uint(p, v < 0 ? 0 - u : u);
}

namespace csv_detail {

/// 10^D.
template <int D>
inline constexpr std::uint64_t kPow10 = [] {
  std::uint64_t s = 1;
  for (int i = 0; i < D; ++i) s *= 10;
  return s;
}();

/// put_fixed_n's fast path: sets n to |x|·10^D rounded to the nearest integer and returns true
/// when that is exact and fmt's rounding (|x|·10^D < 1e15, not within rounding distance of a
/// half); returns false otherwise (then fmt must write x).
template <int D>
[[gnu::always_inline]] inline bool fixed_scaled(double x, std::uint64_t& n) {
  const double a = std::fabs(x);
  const double y = a * static_cast<double>(kPow10<D>);  // within half an ulp of the exact a·10^D
  if (!(y < 1e15)) return false;                        // also NaN and infinity
  // y is in [0, 1e15): the truncation is the floor, and exact both ways.
  const auto whole = static_cast<std::uint64_t>(static_cast<std::int64_t>(y));
  const double frac = y - static_cast<double>(whole);  // exact
  // The nearest integer to the exact a·10^D is the nearest to y unless a half lies within
  // the rounding of y (|y − a·10^D| <= ulp(y)/2 <= y·2^-53); keep well clear of it.
  if (!(std::fabs(frac - 0.5) > y * 4.5e-16)) return false;
  n = whole + (frac > 0.5 ? 1 : 0);
  return true;
}

}  // namespace csv_detail

/// put_fixed with the number of decimals D (1..9) known at compile time.
template <int D>
[[gnu::always_inline]] inline char* put_fixed_n(char* p, double x) {
  static_assert(D >= 1 && D <= 9);
  std::uint64_t n;
  if (!csv_detail::fixed_scaled<D>(x, n)) [[unlikely]]
    return csv_detail::put_fixed_fmt(p, x, D);
  *p = '-';  // kept only for a negative x (and -0), without a branch
  p += std::signbit(x) ? 1 : 0;
  p = csv_detail::put_uint(p, n / csv_detail::kPow10<D>);
  *p++ = '.';
  return csv_detail::put_fraction<D>(p, n % csv_detail::kPow10<D>);
}

/// Writes `x` with `decimals` (1..9) digits after the point at `p`; returns the end. The text
/// is exactly fmt's "{:.Nf}" (the correctly rounded decimal of the binary value, "-" kept for
/// negative values that round to zero, "nan"/"inf"): a fast integer path when |x|·10^N < 1e15
/// and the value is not within rounding distance of a half (then fmt itself writes it).
/// At most 350 characters (|x| up to DBL_MAX goes to fmt).
char* put_fixed(char* p, double x, int decimals);

}  // namespace gm
