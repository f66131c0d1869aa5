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

double tau_for_accel_limit(const Machine& m, const std::vector<double>& a_max_mm_s2,
                           double fallback_s) {
  double ratio = 0.0;
  for (int i = 0; i < m.axis_count(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (k < a_max_mm_s2.size() && a_max_mm_s2[k] > 0.0)
      ratio = std::max(ratio, m.axes[k].v_max_mm_s / a_max_mm_s2[k]);
  }
  if (ratio == 0.0) return fallback_s;
  const double taps = std::ceil(profile_peak_factor(m.profile) * ratio / m.period_s - 1e-9);
  return std::clamp(taps, 1.0, static_cast<double>(kMaxAccDecTaps)) * m.period_s;
}

}  // namespace gm
