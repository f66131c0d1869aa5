// Fast exact decimal formatting of integers and fixed-point doubles for the CSV trace.
#include "trace/csv_number.hpp"

#include <fmt/format.h>

namespace gm {

char* csv_detail::put_uint_long(char* p, std::uint64_t v) {
  if (v < 10000000000000000u) {  // two conversions of eight digits
    const std::uint64_t hi = v / 100000000u;
    p = put_uint8(p, static_cast<std::uint32_t>(hi));
    store_digits8(p, digit_bytes8(static_cast<std::uint32_t>(v - hi * 100000000u)));
    return p + 8;
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

char* csv_detail::put_fixed_fmt(char* p, double x, int decimals) {
  return fmt::format_to(p, "{:.{}f}", x, decimals);
}

char* put_fixed(char* p, double x, int decimals) {
  switch (decimals) {
    case 1:
      return put_fixed_n<1>(p, x);
    case 2:
      return put_fixed_n<2>(p, x);
    case 3:
      return put_fixed_n<3>(p, x);
    case 4:
      return put_fixed_n<4>(p, x);
    case 5:
      return put_fixed_n<5>(p, x);
    case 6:
      return put_fixed_n<6>(p, x);
    case 7:
      return put_fixed_n<7>(p, x);
    case 8:
      return put_fixed_n<8>(p, x);
    case 9:
      return put_fixed_n<9>(p, x);
    default:
      return csv_detail::put_fixed_fmt(p, x, decimals);
  }
}

}  // namespace gm
