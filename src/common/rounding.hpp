// Rounding to the nearest integer, halves away from zero: std::llround, inlined for hot paths.
#pragma once

#include <cmath>
#include <cstdint>

namespace gm {

/// Exactly std::llround(x) (nearest integer, halves away from zero), without the libm call.
/// Finite |x| < 2^63 take the inline path; anything else is handed to std::llround.
inline std::int64_t round_half_away(double x) {
  if (!(std::fabs(x) < 9.2e18)) return std::llround(x);
  const auto i = static_cast<std::int64_t>(x);     // truncated toward zero
  const double frac = x - static_cast<double>(i);  // exact: |x| < 2^52 or x is an integer
  return i + static_cast<std::int64_t>(frac >= 0.5) - static_cast<std::int64_t>(frac <= -0.5);
}

}  // namespace gm
