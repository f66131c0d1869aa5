// Fast exact decimal formatting of integers and fixed-point doubles for the CSV trace.
#include "trace/csv_number.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstring>

namespace gm {

char* put_int(char* p, std::int64_t v) {
  const fmt::format_int f(v);
  std::memcpy(p, f.data(), f.size());
  return p + f.size();
}

char* put_fixed(char* p, double x, int decimals) {
  static constexpr std::uint64_t kPow10[] = {1,      10,      100,      1000,      10000,
                                             100000, 1000000, 10000000, 100000000, 1000000000};
  if (decimals >= 1 && decimals <= 9 && std::isfinite(x)) {
    const std::uint64_t scale = kPow10[decimals];
    const double a = std::fabs(x);
    const double y = a * static_cast<double>(scale);  // within half an ulp of the exact a·10^N
    if (y < 1e15) {
      const double whole = std::floor(y);
      const double frac = y - whole;  // exact
      // The nearest integer to the exact a·10^N is the nearest to y unless a half lies within
      // the rounding of y (|y − a·10^N| <= ulp(y)/2 <= y·2^-53); keep well clear of it.
      if (std::fabs(frac - 0.5) > y * 4.5e-16) {
        const std::uint64_t n = static_cast<std::uint64_t>(whole) + (frac > 0.5 ? 1 : 0);
        if (std::signbit(x)) *p++ = '-';
        const fmt::format_int ip(n / scale);
        std::memcpy(p, ip.data(), ip.size());
        p += ip.size();
        *p++ = '.';
        std::uint64_t f = n % scale;
        for (int i = decimals - 1; i >= 0; --i) {
          p[i] = static_cast<char>('0' + f % 10);
          f /= 10;
        }
        return p + decimals;
      }
    }
  }
  return fmt::format_to(p, "{:.{}f}", x, decimals);
}

}  // namespace gm
