// The tolerance planner's check of a pre-compensated arc: the filter output of the arc alone,
// between its tangent lines, commanded as the interpolator commands it, simulated.
#pragma once

#include "interpolator/arc_compensation.hpp"

#include <Eigen/Core>

#include <vector>

namespace gm {

/// Why the arc alone: the filter is linear and the path's tangent u(s) is a sum of one term per
/// element (an arc contributes u(σ) − u(start) inside it and u(end) − u(start) after it, a corner
/// a step), so y − x(s̄) = Σ h_i (x(s_i) − x(s̄)) + Σ h_i c_i n_i is the sum over the elements of
/// what each does between its tangent lines, rotated (docs/tolerance.md, "Pre-compensated
/// arcs"). The planner's sharing then adds the elements' bounds as before; this class gives the
/// compensated arc's term: the largest |y − x(s̄)| of the isolated arc, simulated in double
/// precision through the weights (rounding is the planner's margin).
class ArcPrecompCheck {
 public:
  /// The FIR's weights h_i (symmetric, Σ = 1) at period T; enabled() is false otherwise.
  ArcPrecompCheck(const std::vector<double>& weights, double period_s);

  bool enabled() const { return rule_.enabled(); }
  const ArcCompensation& rule() const { return rule_; }
  /// Largest path speed at which an arc of `sweep_abs_rad` over `length_mm` of path may be
  /// compensated: A(ωT) >= ArcCompensation::kMinGain with ω = v·|θ|/L.
  double speed_limit_mm_s(double sweep_abs_rad, double length_mm) const;
  /// The term of an arc of radius r, |θ| and path length L planned at v_p (the interpolator's
  /// blend and ramp for v_p): the largest of the isolated arc at constant speeds v_p and 0.6·v_p,
  /// plus the transient of the ramp from v_p to rest and back on the steady arc. mm.
  double error_mm(double radius_mm, double sweep_abs_rad, double length_mm, double v_plan) const;
  /// The isolated arc at speed `v` (path): between moving tangent lines, starting from rest
  /// (the interpolator's ramp) and stopping on its end point; the first sample `phase` of a
  /// sample past a window before the arc: the largest |y − x(s̄)|, mm.
  double isolated_mm(double radius_mm, double sweep_abs_rad, double length_mm, double v_plan,
                     double v, double phase) const;
  /// The ramp's transient on the steady arc, mm.
  double ramp_mm(double radius_mm, double sweep_abs_rad, double length_mm, double v_plan) const;

 private:
  enum class Start { Moving, FromRest };  ///< at speed on the line before, or from rest
  enum class End { Moving, Stop };        ///< on along the line after, or stopping at the end
  /// The filter over in-plane path [p_from, p_to] (samples every vp·T from p_from + phase·vp·T;
  /// from rest: a window at the start, then the ramp), the largest |y − x(s̄)| once the window
  /// is full.
  double run_segment(double p_from, double p_to, double phase, Start start, End end) const;
  Eigen::Vector2d point(double p) const;  ///< the isolated path at in-plane length p

  std::vector<double> h_;
  double period_s_;
  ArcCompensation rule_;
  // The isolated arc being simulated (set by isolated_mm): radius, in-plane length, q = r·|θ|/L,
  // blend length (path), correction at the speed, in-plane step per sample.
  mutable double r_ = 0, lp_ = 0, q_ = 0, len_ = 0, blend_ = 0, c_ = 0, dp_ = 0, v_ = 0, dv_ = 0;
  mutable std::vector<Eigen::Vector2d> ring_;
  mutable std::vector<double> ring_p_;
};

}  // namespace gm
