// Residual vibration (accdec/vibration) and smoothing (planner/filter_moments) of a profile.
#include "cli/vibration_figures.hpp"

#include "accdec/analysis.hpp"
#include "accdec/profile_spec.hpp"
#include "accdec/profiles.hpp"
#include "common/units.hpp"
#include "planner/filter_moments.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace gm::cli {

VibrationFigures vibration_figures(const std::string& profile, double tau_s, double period_s,
                                   double freq_hz, double damping, double feed_mm_min,
                                   double limit) {
  VibrationFigures v;
  v.taps = design_taps(profile, tau_s, period_s);
  v.tau_s = tau_s;
  v.robustness = vibration_robustness(as_double(v.taps.integer), period_s, freq_hz, damping, limit);
  const auto shapers = spec_shapers(parse_profile_spec(profile));
  v.v_continuous = shapers.empty() ? std::numeric_limits<double>::quiet_NaN() : 1.0;
  for (const ShaperImpulses& s : shapers) v.v_continuous *= residual_vibration(s, freq_hz, damping);
  const FilterMoments fm(v.taps, period_s);
  v.sigma_s = std::sqrt(fm.variance_s2());
  v.corner_moment_s = fm.corner_moment_s(0.0);
  v.corner_error_mm =
      fm.corner_error_mm(units::mm_min_to_mm_s(feed_mm_min), std::numbers::pi / 2, 0.0);
  return v;
}

}  // namespace gm::cli
