// Pre-compensated arcs: the radial correction that puts a symmetric FIR's steady output on the
// programmed radius, its blend at the arc's ends and the speed ramp on such arcs.
#pragma once

#include <vector>

namespace gm {

/// The rule both the interpolator (which commands it) and the tolerance planner (which checks
/// it) follow. For symmetric weights h_i (i = 0..N, Σ h_i = 1, centre m) a circle of radius r
/// taken at angular rate ω leaves the filter on radius r·A(ωT), A(ωT) = Σ h_i cos((i − m)ωT),
/// delayed by mT. Commanding it on r + c with c = r·(1/A − 1) puts the steady output on r.
///
/// On an arc the planner marks (Motion::comp_speed_mm_s = v_p > 0, the speed it planned):
///  * c is taken from each sample's actual in-plane angular rate (after override and cap);
///  * c is blended in over the first ℓ and out over the last ℓ of the arc (ℓ =
///    min(L/2, kBlendSamples·T·v_p)), linearly, so the block's ends are its programmed points;
///  * the path speed changes by at most v_p / ramp_samples() per sample (a ramp from 0 to v_p in
///    τ), so that an override step is followed without a transient the filter cannot
///    average out.
/// A(ωT) is tabulated once over [0, limit_omega_t()], where A falls to kMinGain; faster arcs are
/// not compensated (the planner never marks them), and the table clamps there.
class ArcCompensation {
 public:
  static constexpr double kMinGain = 0.5;
  static constexpr int kBlendSamples = 2;
  static constexpr int kTableSteps = 1024;

  ArcCompensation() = default;  ///< off: enabled() is false
  /// From the filter's weights (any; enabled() only if they are symmetric) at period T.
  ArcCompensation(const std::vector<double>& weights, double period_s);

  bool enabled() const { return !table_.empty(); }
  double period_s() const { return period_s_; }
  /// A(ωT) by the closed form.
  double gain_exact(double omega_t) const;
  /// A(ωT) from the table (linear interpolation; ωT beyond the limit is taken at the limit).
  double gain(double omega_t) const {
    const double x = omega_t * inv_step_;
    if (!(x < static_cast<double>(kTableSteps))) return table_.back();
    const auto i = static_cast<int>(x);
    const double f = x - static_cast<double>(i);
    return table_[static_cast<std::size_t>(i)] * (1.0 - f) +
           table_[static_cast<std::size_t>(i) + 1] * f;
  }
  /// Largest ωT with A(ωT) >= kMinGain.
  double limit_omega_t() const { return limit_; }
  /// The radial correction c = r·(1/A − 1) at angular rate `omega_rad_s`, mm.
  double correction_mm(double radius_mm, double omega_rad_s) const {
    return radius_mm * (1.0 / gain(omega_rad_s * period_s_) - 1.0);
  }
  /// ℓ = min(L/2, kBlendSamples·T·v_p), mm.
  double blend_length_mm(double length_mm, double planned_mm_s) const;
  /// Blend weight at `s_mm` along an arc of length `length_mm`: s/ℓ, then 1, then (L − s)/ℓ.
  static double blend(double s_mm, double length_mm, double blend_mm) {
    const double d = s_mm < length_mm - s_mm ? s_mm : length_mm - s_mm;
    if (!(d > 0.0)) return 0.0;
    return d >= blend_mm ? 1.0 : d / blend_mm;
  }
  /// Samples of the ramp from 0 to the planned speed: N + 1, the filter's window.
  int ramp_samples() const { return ramp_samples_; }
  /// Largest change of path speed per sample on an arc planned at `planned_mm_s`, mm/s.
  double speed_step_mm_s(double planned_mm_s) const {
    return planned_mm_s / static_cast<double>(ramp_samples_);
  }

 private:
  std::vector<double> h_;
  double centre_ = 0.0;
  double period_s_ = 0.0;
  std::vector<double> table_;  ///< A at k·limit/kTableSteps, k = 0..kTableSteps
  double limit_ = 0.0;
  double inv_step_ = 0.0;
  int ramp_samples_ = 1;
};

}  // namespace gm
