// Number formatting for the CSV trace: the exact text fmt's "{}" and "{:.Nf}" give, faster.
#pragma once

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
/// The two digits of r (< 100) as a 16-bit value, first digit in the low byte.
inline std::uint64_t pair_bits(unsigned r) {
  return static_cast<std::uint64_t>(static_cast<unsigned char>(kDigitPairs[2 * r])) |
         static_cast<std::uint64_t>(static_cast<unsigned char>(kDigitPairs[2 * r + 1])) << 8;
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

/// Writes v in decimal at p, straight into place; returns the end. Below 10^8 (every count a
/// trace holds in practice) without a loop: the eight digits from four pairs, then the
/// significant ones moved to p as one 8-byte store, so p must have 8 bytes of room.
inline char* put_uint(char* p, std::uint64_t v) {
  if (v < 10) {  // zeros and small following errors are common: a digit or a pair
    *p = static_cast<char>('0' + v);
    return p + 1;
  }
  if (v < 100) {
    put_pair(p, static_cast<unsigned>(v));
    return p + 2;
  }
  if (v < 100000000u) {
    const auto x = static_cast<std::uint32_t>(v);
    const std::uint32_t hi = x / 10000, lo = x - hi * 10000;
    const std::uint32_t a = hi / 100, c = lo / 100;
    const int n = count_digits(v);
    // The eight digits as one word, first digit in the lowest byte (little-endian memory order),
    // then the last n of them shifted down to the first n bytes.
    std::uint64_t w = pair_bits(a) | pair_bits(hi - a * 100) << 16 | pair_bits(c) << 32 |
                      pair_bits(lo - c * 100) << 48;
    w >>= 8 * (8 - n);
    if constexpr (std::endian::native == std::endian::big) w = __builtin_bswap64(w);
    std::memcpy(p, &w, 8);
    return p + n;
  }
  char* const end = p + count_digits(v);
  char* q = end;
  while (v >= 100) {
    const auto r = static_cast<unsigned>(v % 100);
    v /= 100;
    q -= 2;
    put_pair(q, r);
  }
  if (v >= 10)
    put_pair(q - 2, static_cast<unsigned>(v));
  else
    q[-1] = static_cast<char>('0' + v);
  return end;
}

/// Writes exactly D digits of f (< 10^D) at p, leading zeros kept; returns the end.
template <int D>
inline char* put_fraction(char* p, std::uint64_t f) {
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
inline char* put_int(char* p, std::int64_t v) {
  auto u = static_cast<std::uint64_t>(v);
  if (v < 0) {
    *p++ = '-';
    u = 0 - u;
  }
  return csv_detail::put_uint(p, u);
}

/// put_fixed with the number of decimals D (1..9) known at compile time.
template <int D>
inline char* put_fixed_n(char* p, double x) {
  static_assert(D >= 1 && D <= 9);
  constexpr std::uint64_t kScale = [] {
    std::uint64_t s = 1;
    for (int i = 0; i < D; ++i) s *= 10;
    return s;
  }();
  if (std::isfinite(x)) {
    const double a = std::fabs(x);
    const double y = a * static_cast<double>(kScale);  // within half an ulp of the exact a·10^D
    if (y < 1e15) {
      const double whole = std::floor(y);
      const double frac = y - whole;  // exact
      // The nearest integer to the exact a·10^D is the nearest to y unless a half lies within
      // the rounding of y (|y − a·10^D| <= ulp(y)/2 <= y·2^-53); keep well clear of it.
      if (std::fabs(frac - 0.5) > y * 4.5e-16) {
        const std::uint64_t n = static_cast<std::uint64_t>(whole) + (frac > 0.5 ? 1 : 0);
        if (std::signbit(x)) *p++ = '-';
        p = csv_detail::put_uint(p, n / kScale);
        *p++ = '.';
        return csv_detail::put_fraction<D>(p, n % kScale);
      }
    }
  }
  return csv_detail::put_fixed_fmt(p, x, D);
}

/// Writes `x` with `decimals` (1..9) digits after the point at `p`; returns the end. The text
/// is exactly fmt's "{:.Nf}" (the correctly rounded decimal of the binary value, "-" kept for
/// negative values that round to zero, "nan"/"inf"): a fast integer path when |x|·10^N < 1e15
/// and the value is not within rounding distance of a half (then fmt itself writes it).
/// At most 350 characters (|x| up to DBL_MAX goes to fmt).
char* put_fixed(char* p, double x, int decimals);

}  // namespace gm
