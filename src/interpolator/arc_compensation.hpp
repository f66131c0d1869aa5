// Pre-compensated arcs: the radial correction that puts a filter's steady output on the
// programmed radius, the 2-D offsets at the arc's ends and the speed ramp on such arcs.
#pragma once

#include "interpolator/arc_end_rows.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace gm {

/// The rule both the interpolator (which commands it) and the tolerance planner (which checks
/// it) follow. For symmetric weights h_i (i = 0..N, Σ h_i = 1, centre m) a circle of radius r
/// taken at angular rate ω leaves the filter on radius r·A(ωT), A(ωT) = Σ h_i cos((i − m)ωT),
/// delayed by mT. Commanding it on r + c with c = r·(1/A − 1) puts the steady output on r. Weights
/// that are not symmetric (the FIR and servo chain planned with tolerance_on = encoder) leave
/// the circle on r·|C(e^{jωT})|, C = Σ h_k e^{−jkωT}, turned by arg C: A is then |C|, and an
/// arc's end takes the rows fitted for the weights reversed (an end is a start seen backwards).
///
/// On an arc the planner marks (Motion::comp_speed_mm_s = v_p > 0, the speed it planned):
///  * c is taken from each sample's actual in-plane angular rate (after override and cap);
///  * at the arc's ends the command takes the end rows (arc_end_rows.hpp): offsets radial and
///    along the path, by the sample's advances from the start (its count since the arc's first
///    sample plus how far past the start that one lay, of its advance) and to the end (the
///    samples still on the arc after it, predicted by the speed ramp, plus the last one's
///    remainder: advances_to_end), so the block's ends are its programmed points; at the
///    end the rows for a stop where the command stops there (Motion::comp_stops_at_end). An arc
///    shorter than ArcEndRows::kSpan + 1 samples at v_p (whose ends would overlap) takes the
///    radial blend instead (c over the first and last ℓ = min(L/2, kBlendSamples·T·v_p),
///    linearly), below kSpan samples wholly, between the two mixed in proportion (rows_weight);
///  * the path speed changes by at most v_p / ramp_samples() per sample (a ramp from 0 to v_p in
///    τ), so that an override step is followed without a transient the filter cannot
///    average out; it holds over the end rows' last kSpan samples (next_speed), and in the
///    window after the arc an override's fall keeps that step (the interpolator): a feed hold
///    there would otherwise stop the command under rows commanded for a path that goes on.
/// A(ωT) is tabulated once over [0, limit_omega_t()], where A falls to kMinGain; faster arcs are
/// not compensated (the planner never marks them), and the table clamps there.
class ArcCompensation {
 public:
  static constexpr double kMinGain = 0.5;
  static constexpr double kTaper = 0.1;
  static constexpr int kBlendSamples = 2;
  static constexpr int kTableSteps = 1024;

  /// A sample's offset from the arc, mm: outwards and along the motion.
  struct Offset {
    double radial_mm = 0.0, along_mm = 0.0;
  };

  ArcCompensation() = default;  ///< off: enabled() is false
  /// From the filter's weights (Σ = 1; enabled() unless the gain never falls to kMinGain) at
  /// period T. `end_rows` false: every arc takes the radial blend (planned for the table with
  /// servos that differ, whose mismatch the rows' jumps of the command would excite).
  ArcCompensation(const std::vector<double>& weights, double period_s, bool end_rows = true);

  bool enabled() const { return !table_.empty(); }
  double period_s() const { return period_s_; }
  /// A(ωT) by the closed form (|C(e^{jωT})| for weights that are not symmetric).
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
  /// At least max |1/A − 1| over ωT in [0, omega_t] (A from the table, interpolated or clamped):
  /// the largest |c|/r there.
  double correction_ratio_cap(double omega_t) const {
    const double x = omega_t * inv_step_;
    const std::size_t i = x < static_cast<double>(kTableSteps)
                              ? static_cast<std::size_t>(std::max(x, 0.0)) + 1
                              : static_cast<std::size_t>(kTableSteps);
    return ratio_max_[i];
  }
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
  /// The weight of the end rows against the radial blend on an arc of `length_mm` planned at
  /// `planned_mm_s`: 1 from kSpan + 1 samples of travel at that speed, 0 below kSpan, a
  /// smoothstep between.
  /// 0 for a filter whose window does not taper (its first weight above kTaper of the
  /// largest: the linear profile), whose hard edges make the rows' effect depend on where the
  /// arc's ends fall within a window, for one longer than ArcEndRows::kMaxWindow weights (the
  /// rows' fit grows as the window's square), and when the rule was built without `end_rows`;
  /// such arcs keep the blend.
  double rows_weight(double length_mm, double planned_mm_s) const {
    if (!rows_on_) return 0.0;
    const double t =
        std::clamp(length_mm / (period_s_ * planned_mm_s) - ArcEndRows::kSpan, 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);  // smooth: the arc's term has no corner in its length
  }
  /// The path the end rows or the blend cover at each end of an arc planned at v_p (at speeds
  /// up to v_p): min(L/2, kSpan·T·v_p), mm.
  double end_length_mm(double length_mm, double planned_mm_s) const {
    return std::min(0.5 * length_mm, ArcEndRows::kSpan * period_s_ * planned_mm_s);
  }
  /// The command's offset at a sample on an arc of radius r whose in-plane advance is x·r
  /// (x = ωT > 0): `from_start` and `to_end` of its advances from the arc's start and to its
  /// end, `rows` = rows_weight(), `blend_weight` the blend's at the sample (blend()); `stops`:
  /// the command stops on the arc's end point (the end rows for a stop).
  Offset offset(double radius_mm, double x, double from_start, double to_end, double rows,
                double blend_weight, bool stops, bool start_distance = false,
                bool end_distance = false) const {
    const double c = radius_mm * (1.0 / gain(x) - 1.0);
    if (!(rows > 0.0)) return {blend_weight * c, 0.0};  // the rows are not fitted for it
    double radial = 1.0, along = 0.0;
    if (from_start < ArcEndRows::kSpan) {
      const ArcEndRows::Shape e = start_rows().at(
          from_start, x,
          start_distance ? ArcEndRows::Way::MovingDistance : ArcEndRows::Way::Moving);
      radial += e.radial - 1.0;
      along += e.along;
    }
    if (to_end < ArcEndRows::kSpan) {
      const ArcEndRows::Shape e = end_rows().at(to_end, x,
                                                stops          ? ArcEndRows::Way::Stopping
                                                : end_distance ? ArcEndRows::Way::MovingDistance
                                                               : ArcEndRows::Way::Moving);
      radial += e.radial - 1.0;
      along -= e.along;
    }
    return {(rows * radial + (1.0 - rows) * blend_weight) * c, rows * along * c};
  }
  /// The speed of a compensated arc's next sample: `target` ramped from the last sample's speed
  /// `last` by at most `step`, and at most `cap`.
  static double ramped(double last, double target, double step, double cap) {
    const double lo = last > step ? last - step : 0.0;
    const double v = target < lo ? lo : target > last + step ? last + step : target;
    return v < cap ? v : cap;
  }
  /// The speed of the sample after one at `last`, `left_mm` of the arc before it: ramped(),
  /// except that the speed holds while that sample would end within the end rows' span at
  /// `last` (ArcEndRows::kSpan advances), so that the rows there meet the end where their
  /// first sample predicted it; the window after the arc takes a fall of the override (the
  /// interpolator ramps it there).
  double next_speed(double last, double target, double step, double cap, double left_mm) const {
    if (last > 0.0 && left_mm < ArcEndRows::kSpan * last * period_s_)
      return last < cap ? last : cap;
    return ramped(last, target, step, cap);
  }
  /// The advances to the arc's end of a sample `left_mm` before it at speed `v` (> 0), the speed
  /// ramped towards `target` (next_speed()) from it on: the count of the samples still on the arc
  /// after it, plus the last one's distance to the end over the next sample's advance (0..1],
  /// as the interpolator's loop will move (a sample stays on the block while its advance is
  /// below what is left, less kLengthEps). ArcEndRows::kSpan or more: farther.
  double advances_to_end(double left_mm, double v, double target, double step, double cap) const {
    constexpr double kLengthEps = 1e-9;  // the interpolator's
    // No sample advances more than cap·T (next_speed is at most cap): from kSpan + 1 of those
    // (and the slack) before the end on, the loop would count to kSpan. Most samples are there.
    if (left_mm > (ArcEndRows::kSpan + 1) * cap * period_s_ + 2.0 * kLengthEps)
      return ArcEndRows::kSpan;
    for (int j = 0; j < ArcEndRows::kSpan; ++j) {
      const double next = next_speed(v, target, step, cap, left_mm);
      if (!(next > 0.0)) break;  // held: no end in sight
      const double adv = next * period_s_;
      if (!(adv < left_mm - kLengthEps)) return j + std::min(1.0, left_mm / adv);
      left_mm -= adv;
      v = next;
    }
    return ArcEndRows::kSpan;
  }
  /// The largest |radial| + |along| of offset() over a sample's advances, both ends reaching
  /// it, in units of c at rate x: 1 + 2·max(|radial − 1| + |along|) over the end rows' knots
  /// of both ways, and of the distance's with `distance` (1 without the rows: the blend is
  /// radial, at most c).
  double largest_offset_factor(double x, bool distance = false) const {
    if (!rows_on_) return 1.0;
    double worst = 0.0;
    for (const ArcEndRows* rows : {&start_rows(), &end_rows()}) {
      for (const ArcEndRows::Way way : {ArcEndRows::Way::Moving, ArcEndRows::Way::Stopping})
        worst = std::max(worst, rows->largest_deviation(x, way));
      if (distance)
        worst = std::max(worst, rows->largest_deviation(x, ArcEndRows::Way::MovingDistance));
      if (h_reversed_.empty()) break;  // symmetric: the end's rows are the start's
    }
    return 1.0 + 2.0 * worst;
  }
  /// The fastest speed a sample `left_mm` before a point the arc's speed must be down to `exit`
  /// at (> 0) may take, so that the ramp (at most `step` a sample) gets there: exit + m·step,
  /// m the largest whole number of steps whose samples, this one included, cover at most
  /// left_mm (T·(m·exit + step·m(m + 1)/2)).
  double braking_speed(double left_mm, double exit, double step) const {
    const double b = exit + 0.5 * step,
                 m = (std::sqrt(b * b + 2.0 * step * left_mm / period_s_) - b) / step;
    return exit + std::floor(std::max(0.0, m)) * step;
  }
  /// Samples of the ramp from 0 to the planned speed: N + 1, the filter's window.
  int ramp_samples() const { return ramp_samples_; }
  /// Largest change of path speed per sample on an arc planned at `planned_mm_s`, mm/s.
  double speed_step_mm_s(double planned_mm_s) const {
    return planned_mm_s / static_cast<double>(ramp_samples_);
  }

 private:
  std::vector<double> h_;
  /// ratio_max_[k] = max_{j ≤ k} |1/table_[j] − 1| (times 1 + 10⁻⁹ for the interpolation's
  /// rounding): correction_ratio_cap.
  std::vector<double> ratio_max_;
  double centre_ = 0.0;
  double period_s_ = 0.0;
  std::vector<double> table_;  ///< A at k·limit/kTableSteps, k = 0..kTableSteps
  double limit_ = 0.0;
  double inv_step_ = 0.0;
  int ramp_samples_ = 1;
  bool rows_on_ = false;   ///< the end rows apply (rows_weight)
  bool symmetric_ = true;  ///< h_ symmetric about its centre: A(ωT) real
  /// The rows of the arc's start, fitted when an arc first needs them (ArcEndRows::shared).
  const ArcEndRows& start_rows() const {
    if (!rows_) rows_ = ArcEndRows::shared(h_, period_s_, limit_);
    return *rows_;
  }
  /// The rows of its end: an end is a start seen backwards in time, through the weights
  /// reversed (the same weights when they are symmetric).
  const ArcEndRows& end_rows() const {
    if (h_reversed_.empty()) return start_rows();
    if (!rows_reversed_) rows_reversed_ = ArcEndRows::shared(h_reversed_, period_s_, limit_);
    return *rows_reversed_;
  }
  std::vector<double> h_reversed_;  ///< h_ backwards when it is not symmetric, else empty
  mutable std::shared_ptr<const ArcEndRows> rows_, rows_reversed_;
};

}  // namespace gm
