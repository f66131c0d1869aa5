// Fig. 9: Steps 1-4 of the Acc/Dec design, increasing tau by one period until the limits hold.
#include "accdec/design_procedure.hpp"

#include "accdec/analysis.hpp"
#include "accdec/profile_spec.hpp"

#include <algorithm>

namespace gm {

DesignAttempt check_limits(const Taps& taps, double tau_s, double period_s,
                           const DesignLimits& limits) {
  DesignAttempt a;
  a.tau_s = tau_s;
  a.taps = taps;
  const double v = limits.v_step_m_s;
  const auto b = as_double(taps.integer);
  const double bs = static_cast<double>(taps.b_s);
  a.peak_velocity_m_s = v;
  a.peak_accel_m_s2 = peak_acceleration(b, v, period_s);
  a.peak_force_N = limits.mass_kg * a.peak_accel_m_s2 + limits.damping_kg_s * v;
  a.peak_power_W = a.peak_force_N * v;
  // Along the step response: V'[k] = V·Σ_{i<k} b_i/b_s, a'[k] = V·b_{k-1}/(T·b_s) (Eq. 7).
  double cum = 0.0;
  for (double bi : b) {
    cum += bi;
    const double vel = v * cum / bs;
    const double f = limits.mass_kg * v * bi / (period_s * bs) + limits.damping_kg_s * vel;
    a.profile_force_N = std::max(a.profile_force_N, f);
    a.profile_power_W = std::max(a.profile_power_W, f * vel);
  }
  a.v_ok = a.peak_velocity_m_s <= limits.v_max_m_s;
  a.f_ok = a.peak_force_N <= limits.f_max_N;
  a.p_ok = a.peak_power_W <= limits.p_max_W;
  return a;
}

std::vector<DesignAttempt> design_procedure(std::string_view profile_spec, double tau_s,
                                            double period_s, const DesignLimits& limits,
                                            int max_attempts) {
  const bool fixed = parse_profile_spec(profile_spec).fixed_length(period_s) > 0;
  std::vector<DesignAttempt> attempts;
  int n = tap_count(tau_s, period_s);
  for (int k = 0; k < std::max(1, max_attempts); ++k, ++n) {
    const double tau = k == 0 ? tau_s : n * period_s;
    attempts.push_back(
        check_limits(design_taps(profile_spec, tau, period_s), tau, period_s, limits));
    // A larger tau cannot help the velocity limit (V' = V), and fixed-length profiles cannot grow.
    if (attempts.back().ok() || fixed || !attempts.back().v_ok) break;
  }
  return attempts;
}

}  // namespace gm
