// Closed forms of the Acc/Dec filter's contour error: corner moment D(P), variance, feed limits.
#pragma once

#include "accdec/taps.hpp"

#include <vector>

namespace gm {

/// What the tolerance planner needs to know of a designed filter with weights h_i = b_i / b_s
/// (the integer taps FirAccDec applies), at period T. All times in seconds.
///
/// A corner passed at speed V, the interpolator pausing P seconds at the vertex: an output
/// sample at time t (corner reached at 0) mixes pre-corner inputs a(t) = V·Σ h_i (iT − t)⁺ before
/// the vertex and post-corner inputs b(t) = V·Σ h_i (t − iT − P)⁺ after it, and lies
/// min(a, b)·sin φ from the path (φ the turn) and at most (a + b)… from the vertex. The largest
/// min(a, b) over t is V·D(P), D(P) = max_t min(A(t), B(t − P)); for symmetric taps (centre
/// m = Σ i·h_i) D(P) = T·Σ h_i·max(i − m − P/(2T), 0), and D(0) = T·Σ h_i·max(m − i, 0).
class FilterMoments {
 public:
  FilterMoments(const Taps& taps, double period_s);
  /// Any linear chain given by its weights c_k at period T (Σ c_k = 1), e.g. FIR + servo
  /// (planner/servo_response.hpp). The c_k may be negative. While the chain's step response
  /// S_k = Σ_{j≤k} c_j stays within [0, 1], A(t) = Σ c_k (kT − t)⁺ = ∫_t^∞ (1 − S) and B are
  /// monotone in the speed and the FIR's D(P) holds as it is. If S overshoots 1 (or dips below
  /// 0), D(P) = max(max_t min(A⁺(t), B⁺(t − P)), ∫(S − 1)⁺, ∫S⁻) (absolute moments;
  /// docs/tolerance.md), the window grows by the overshoot time and zone_floor_s() is the window.
  FilterMoments(std::vector<double> weights, double period_s);

  double period_s() const { return period_s_; }
  double tau_s() const { return period_s_ * static_cast<double>(h_.size()); }
  /// N: the filter order (N + 1 taps).
  int order() const { return static_cast<int>(h_.size()) - 1; }
  const std::vector<double>& weights() const { return h_; }
  /// m = Σ i·h_i, in samples.
  double centre() const { return centre_; }
  /// σ² = T²·Σ h_i (i − m)², s²: a path of curvature κ taken at speed ≤ V is left by at most
  /// κ·V²·σ²/2 (the steady radius loss of Eq. 13/14 is below it). With negative weights the
  /// bound T²·Σ |c_i|·(Σ_j |c_j|·|i − j|)² instead (|s_i − s̄| ≤ V·T·Σ_j |c_j|·|i − j|).
  double variance_s2() const { return variance_s2_; }
  /// M₁ = T·Σ h_i·|i − m|, s: the first absolute moment, Σ h_i·|s_i − s̄| ≤ V·M₁ at speeds ≤ V
  /// (it grows with every path increment when h ≥ 0; = 2·D(0) for symmetric taps). With negative
  /// weights the bound Σ |c_i|·T·Σ_j |c_j|·|i − j| instead.
  double abs_moment_s() const { return abs_moment_s_; }

  /// Shortest zone (time either side of a corner at the capped speed) whatever the pause: 0 when
  /// the chain's step response stays in [0, 1], else the whole window (the output can run past
  /// a vertex before and long after the input passes it).
  double zone_floor_s() const { return zone_floor_s_; }
  double overshoot_s() const { return over_s_; }
  double undershoot_s() const { return under_s_; }
  /// D(P), s: the corner moment with a pause of `pause_s` at the vertex (computed directly as
  /// max_t min(A(t), B(t − P)), valid for any taps). 0 for P ≥ N·T.
  double corner_moment_s(double pause_s) const;
  /// D(P) by the symmetric closed form T·Σ h_i·max(i − m − P/(2T), 0).
  double corner_moment_closed_s(double pause_s) const;

  /// A(ωT) = Σ h_i·cos((i − m)·ωT): for symmetric taps D(e^{jωT}) = e^{−jωmT}·A(ωT), so a circle
  /// of radius r taken at angular rate ω comes out of the filter on radius r·A(ωT) in steady
  /// state, delayed by mT (Eq. 13/14).
  double amplitude(double omega_t) const;
  /// The radius to command so that the steady output lies on `radius_mm`: R / A(ωT).
  double compensated_radius_mm(double radius_mm, double omega_t) const {
    return radius_mm / amplitude(omega_t);
  }
  /// b_i = b_{N−i} (the output of a circle is then a circle, only scaled and delayed).
  bool symmetric() const;

  /// Contour error (distance to the two legs) of an isolated corner turning by `turn_rad` taken
  /// at `speed_mm_s` with a pause `pause_s` at the vertex: V·D(P)·sin φ (φ ≤ π).
  double corner_error_mm(double speed_mm_s, double turn_rad, double pause_s) const;
  /// Distance of the output from the vertex at the crossing instant: 2·V·D(P)·sin(φ/2).
  double vertex_error_mm(double speed_mm_s, double turn_rad, double pause_s) const;
  /// Largest speed for which corner_error_mm stays within `tol_mm` (infinity if D(P)·sinφ = 0).
  double largest_corner_speed_mm_s(double tol_mm, double turn_rad, double pause_s) const;
  /// Shortest pause for which an isolated corner at `speed_mm_s` stays within `tol_mm`
  /// (bisection on the monotone D(P); 0 when no pause is needed; ≤ N·T).
  double shortest_pause_s(double tol_mm, double turn_rad, double speed_mm_s) const;

 private:
  friend class CornerMomentGrid;  // runs corner_moment_s's bisection with running sums

  void init();
  double pre_moment(double t) const;   // A(t) = Σ h_i (iT − t)⁺
  double pre_pos(double t) const;      // A⁺(t) = ∫_t^∞ (1 − S)⁺
  double post_pos(double t) const;     // B⁺(t) = ∫_{−∞}^t S⁺
  double post_moment(double t) const;  // B(t) = Σ h_i (t − iT)⁺

  double period_s_;
  std::vector<double> h_;
  double centre_ = 0.0;
  double variance_s2_ = 0.0;
  double abs_moment_s_ = 0.0;
  double over_s_ = 0.0;   ///< ∫ (S − 1)⁺: step response above 1 (overshoot area), s
  double under_s_ = 0.0;  ///< ∫ S⁻: below 0, s
  double zone_floor_s_ = 0.0;
};

}  // namespace gm
