// Frequency-domain analysis of Acc/Dec taps: amplitude response, radius loss (Eq. 13-19), Eq. 7.
#pragma once

#include "accdec/taps.hpp"

#include <vector>

namespace gm {

/// |D(e^{jωT})| = |Σ b_i e^{-j i ωT}| / Σ b_i for any taps b_i >= 0 (Eq. 8; Eq. 13/14 are the
/// symmetric special case). `omega_T` in radians per sample.
double amplitude_response(const std::vector<double>& taps, double omega_T);

/// Radius loss of a circle of `radius` at tangential speed `v_tan` through the sampled filter:
/// R(1 − |D(e^{jωT})|) with ω = v_tan/radius (steady state, Eq. 9-12). Same length unit as
/// `radius` (v_tan in that unit per second, period in s). Computed without cancellation as
/// R(1−|D|²)/(1+|D|), 1−|D|² = (2/b_s²) Σ_{i<k} b_i b_k · 2sin²((k−i)ωT/2).
double radius_loss_sampled(const std::vector<double>& taps, double radius, double v_tan,
                           double period_s);

/// Eq. 18 (linear Acc/Dec, continuous approximation Eq. 17): R − 2R/(τω)·sin(τω/2), ω = V/R.
/// Computed as R(1 − sin(u)/u), u = τω/2, with a series for small u (no cancellation).
double radius_loss_linear_continuous(double radius, double v_tan, double tau_s);

/// Eq. 19: (τV)²/(24R).
double radius_loss_linear_approx(double radius, double v_tan, double tau_s);

/// Eq. 7: peak acceleration of the filter output for a velocity step v (any unit/s):
/// v·max(b_i)/(T·b_s).
double peak_acceleration(const std::vector<double>& taps, double v_step, double period_s);

/// Largest |A_integer(ω) − A_real(ω)| over a grid of `points` frequencies in [0, π] rad/sample:
/// the frequency-response error of the Step 3 integer quantisation.
double quantisation_error(const Taps& taps, int points = 2048);

/// The integer taps as doubles (for the analysis functions).
std::vector<double> as_double(const std::vector<std::int64_t>& taps);

}  // namespace gm
