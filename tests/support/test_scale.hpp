// Test helper: how many cases a property sweep runs, shrunk under the sanitizers by
// GMOTION_TEST_SCALE.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace gmtest {

/// `n` times GMOTION_TEST_SCALE (a fraction in (0, 1], unset = 1), at least 1. The asan test
/// preset sets it so the property sweeps still run under ASan+UBSan, on fewer random cases; the
/// default preset runs every case.
inline int scaled(int n) {
  const char* env = std::getenv("GMOTION_TEST_SCALE");
  const double scale = env ? std::strtod(env, nullptr) : 1.0;
  if (!(scale > 0.0) || scale >= 1.0) return n;
  return std::max(1, static_cast<int>(std::lround(n * scale)));
}

}  // namespace gmtest
