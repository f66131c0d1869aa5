// τ from acceleration limits: the profile's peak-to-mean tap ratio and the per-axis V/A.
#include "accdec/accel_limit.hpp"

#include "accdec/taps.hpp"
#include "common/status.hpp"

#include <algorithm>
#include <cmath>

namespace gm {

double profile_peak_factor(const std::string& profile) {
  constexpr int kTaps = 1000;
  try {
    const Taps t = design_taps(profile, kTaps * 1e-3, 1e-3);
    return *std::max_element(t.real.begin(), t.real.end()) * static_cast<double>(t.real.size());
  } catch (const InputError&) {
    return 1.0;  // a fixed-length profile (custom, cascade) cannot be designed at 1000 taps
  }
}

double tau_for_accel_limit(const std::string& profile, double period_s,
                           const std::vector<double>& v_max_mm_s,
                           const std::vector<double>& a_max_mm_s2, double fallback_s) {
  double ratio = 0.0;
  for (std::size_t k = 0; k < v_max_mm_s.size() && k < a_max_mm_s2.size(); ++k)
    if (a_max_mm_s2[k] > 0.0) ratio = std::max(ratio, v_max_mm_s[k] / a_max_mm_s2[k]);
  if (ratio == 0.0) return fallback_s;
  const double taps = std::ceil(profile_peak_factor(profile) * ratio / period_s - 1e-9);
  return std::clamp(taps, 1.0, static_cast<double>(kMaxAccDecTaps)) * period_s;
}

}  // namespace gm
