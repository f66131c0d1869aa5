// The Fig. 9 design procedure: Steps 1-4, growing tau one period at a time until Eq. 26 holds.
#pragma once

#include "accdec/taps.hpp"

#include <string>
#include <vector>

namespace gm {

/// System limitations of Step 4 (Eq. 26) and the velocity step used for Eq. 7.
/// Defaults are the paper's section 6 example.
struct DesignLimits {
  double v_max_m_s = 1.0;       ///< velocity limit V_Max
  double mass_kg = 500.0;       ///< equivalent mass m
  double damping_kg_s = 500.0;  ///< equivalent viscous damping c
  double f_max_N = 4000.0;      ///< force limit F_Max
  double p_max_W = 500.0;       ///< power limit P_Max
  double v_step_m_s = 0.1;      ///< largest (overridden) velocity step V fed to the filter
};

/// One attempt of the procedure: the taps for one tau and the Step 4 figures.
struct DesignAttempt {
  double tau_s = 0;
  Taps taps;
  double peak_velocity_m_s = 0;  ///< V'max = V (the output is a convex combination of inputs)
  double peak_accel_m_s2 = 0;    ///< Eq. 7 with the applied (integer) taps: V·max b_i/(T·b_s)
  double peak_force_N = 0;       ///< m·a_peak + c·V (Eq. 29's bound)
  double peak_power_W = 0;       ///< peak_force·V (Eq. 29)
  double profile_force_N = 0;    ///< max_k m·a'[k] + c·V'[k] along the step response (<= bound)
  double profile_power_W = 0;    ///< max_k (m·a'[k] + c·V'[k])·V'[k]
  bool v_ok = false, f_ok = false, p_ok = false;
  bool ok() const { return v_ok && f_ok && p_ok; }
};

/// Step 4 for designed taps: the Eq. 7 / Eq. 26 figures against `limits` (period in s).
DesignAttempt check_limits(const Taps& taps, double tau_s, double period_s,
                           const DesignLimits& limits);

/// Fig. 9: design at tau, check the limits; while they fail, tau += T and repeat, at most
/// `max_attempts` designs. Returns every attempt (the last one is the result; it is ok() unless
/// the attempts ran out or the profile has a fixed length — custom/cascade — which stops after
/// the first). Throws gm::InputError for a bad spec, tau or T (see design_taps).
std::vector<DesignAttempt> design_procedure(std::string_view profile_spec, double tau_s,
                                            double period_s, const DesignLimits& limits,
                                            int max_attempts = 2000);

}  // namespace gm
