// Fast exact decimal formatting of integers and fixed-point doubles for the CSV trace.
#include "trace/csv_number.hpp"

#include <fmt/format.h>

namespace gm {

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
