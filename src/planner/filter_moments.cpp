// FilterMoments: the corner moment D(P) by direct maximisation and by the symmetric closed form.
#include "planner/filter_moments.hpp"

#include "common/status.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace gm {

FilterMoments::FilterMoments(const Taps& taps, double period_s) : period_s_(period_s) {
  if (taps.integer.empty() || taps.b_s <= 0) throw InputError("filter moments need taps");
  h_.reserve(taps.integer.size());
  for (auto b : taps.integer) h_.push_back(static_cast<double>(b) / static_cast<double>(taps.b_s));
  init();
}

FilterMoments::FilterMoments(std::vector<double> weights, double period_s)
    : period_s_(period_s), h_(std::move(weights)) {
  if (h_.empty() || !(period_s > 0.0)) throw InputError("filter moments need weights");
  double s = 0.0;
  for (std::size_t k = 0; k < h_.size(); ++k) {
    // C on ((k−1)T, kT] is 1 − S_{k−1}; S on (kT, (k+1)T] is S_k.
    over_s_ += period_s_ * std::max(s - 1.0, 0.0);
    s += h_[k];
    under_s_ += period_s_ * std::max(-s, 0.0);
  }
  if (std::abs(s - 1.0) > 1e-9) throw InputError("filter moments: the weights must sum to 1");
  // Sums of non-negative weights end a few ulp above 1: no overshoot below 1e-12 s (1 nm at
  // 1 m/s), so the FIR alone plans exactly as with the Taps constructor.
  if (over_s_ < 1e-12 && under_s_ < 1e-12) over_s_ = under_s_ = 0.0;
  if (over_s_ > 0.0 || under_s_ > 0.0) {
    // The output can run past a vertex before the input reaches it (by at most V·overshoot
    // area of path): the window is lengthened by whole samples covering that time, and the
    // planner's zones are the whole window whatever the pause (zone_floor_s).
    const auto extra = static_cast<std::size_t>(std::ceil(over_s_ / period_s_)) + 1;
    h_.insert(h_.end(), extra, 0.0);
    zone_floor_s_ = tau_s();
  }
  init();
}

void FilterMoments::init() {
  for (std::size_t i = 0; i < h_.size(); ++i) centre_ += static_cast<double>(i) * h_[i];
  const bool signed_weights = std::any_of(h_.begin(), h_.end(), [](double c) { return c < 0.0; });
  // With signed weights, Σ_j |c_j|·|i − j| for every i from running sums of |c_j| and j·|c_j| on
  // either side of i: linear in the length (a lightly damped structural mode in the encoder plan's
  // chain gives 55,638 weights, which the double sum took 34 s over).
  double right = 0.0, right_moment = 0.0, left = 0.0, left_moment = 0.0;
  if (signed_weights)
    for (std::size_t j = 0; j < h_.size(); ++j) {
      right += std::abs(h_[j]);
      right_moment += static_cast<double>(j) * std::abs(h_[j]);
    }
  for (std::size_t i = 0; i < h_.size(); ++i) {
    double d = (static_cast<double>(i) - centre_) * period_s_;
    const double x = static_cast<double>(i);
    if (signed_weights) {  // |s_i − s̄| ≤ V·T·Σ_j |c_j|·|i − j|
      right -= std::abs(h_[i]);
      right_moment -= x * std::abs(h_[i]);
      d = (x * left - left_moment + right_moment - x * right) * period_s_;
      left += std::abs(h_[i]);
      left_moment += x * std::abs(h_[i]);
    }
    variance_s2_ += std::abs(h_[i]) * d * d;
    abs_moment_s_ += std::abs(h_[i]) * std::abs(d);
  }
}

double FilterMoments::pre_moment(double t) const {
  double a = 0.0;
  for (std::size_t i = 0; i < h_.size(); ++i)
    a += h_[i] * std::max(static_cast<double>(i) * period_s_ - t, 0.0);
  return a;
}

double FilterMoments::post_moment(double t) const {
  double b = 0.0;
  for (std::size_t i = 0; i < h_.size(); ++i)
    b += h_[i] * std::max(t - static_cast<double>(i) * period_s_, 0.0);
  return b;
}

double FilterMoments::pre_pos(double t) const {
  double a = 0.0, c = 1.0;  // c = C_k = Σ_{i≥k} h_i on ((k−1)T, kT]
  for (std::size_t k = 0; k < h_.size(); ++k) {
    const double hi = static_cast<double>(k) * period_s_, lo = hi - period_s_;
    a += std::max(c, 0.0) * std::clamp(hi - std::max(t, lo), 0.0, period_s_);
    c -= h_[k];
  }
  return a;
}

double FilterMoments::post_pos(double t) const {
  double b = 0.0, s = 0.0;  // s = S_k = Σ_{i≤k} h_i on (kT, (k+1)T]
  for (std::size_t k = 0; k < h_.size(); ++k) {
    s += h_[k];
    const double lo = static_cast<double>(k) * period_s_, hi = lo + period_s_;
    if (k + 1 == h_.size()) return b + std::max(s, 0.0) * std::max(t - lo, 0.0);
    b += std::max(s, 0.0) * std::clamp(std::min(t, hi) - lo, 0.0, period_s_);
  }
  return b;
}

double FilterMoments::corner_moment_s(double pause_s) const {
  if (over_s_ > 0.0 || under_s_ > 0.0) {
    // Signed moments: min(a, b) lies in [−V·max(A⁻, B⁻), V·min(A⁺, B⁺)] (docs/tolerance.md).
    double lo = -period_s_, hi = tau_s() + pause_s + period_s_;
    for (int it = 0; it < 200 && hi - lo > 1e-15 * (1.0 + hi); ++it) {
      const double mid = 0.5 * (lo + hi);
      (pre_pos(mid) > post_pos(mid - pause_s) ? lo : hi) = mid;
    }
    const double t = 0.5 * (lo + hi);
    const double d = std::max(0.0, std::min(pre_pos(t), post_pos(t - pause_s)));
    return std::max({d, over_s_, under_s_});
  }
  // A(t) falls and B(t − P) rises with t: min(A, B) is largest where they cross.
  double lo = -period_s_, hi = tau_s() + pause_s + period_s_;
  for (int it = 0; it < 200 && hi - lo > 1e-15 * (1.0 + hi); ++it) {
    const double mid = 0.5 * (lo + hi);
    if (pre_moment(mid) > post_moment(mid - pause_s))
      lo = mid;
    else
      hi = mid;
  }
  const double t = 0.5 * (lo + hi);
  return std::max(0.0, std::min(pre_moment(t), post_moment(t - pause_s)));
}

double FilterMoments::corner_moment_closed_s(double pause_s) const {
  double d = 0.0;
  for (std::size_t i = 0; i < h_.size(); ++i)
    d += h_[i] * std::max(static_cast<double>(i) - centre_ - pause_s / (2.0 * period_s_), 0.0);
  return period_s_ * d;
}

double FilterMoments::amplitude(double omega_t) const {
  double a = 0.0;
  for (std::size_t i = 0; i < h_.size(); ++i)
    a += h_[i] * std::cos((static_cast<double>(i) - centre_) * omega_t);
  return a;
}

bool FilterMoments::symmetric() const {
  // The weights end in zeros when an overshooting chain was lengthened: compare the support.
  const auto [lo, hi] = weights_support(h_);
  for (std::size_t i = lo, j = hi; i < j; ++i)
    if (h_[i] != h_[--j]) return false;
  return true;
}

double FilterMoments::corner_error_mm(double speed_mm_s, double turn_rad, double pause_s) const {
  return speed_mm_s * corner_moment_s(pause_s) * std::sin(turn_rad);
}

double FilterMoments::vertex_error_mm(double speed_mm_s, double turn_rad, double pause_s) const {
  return 2.0 * speed_mm_s * corner_moment_s(pause_s) * std::sin(turn_rad / 2.0);
}

double FilterMoments::largest_corner_speed_mm_s(double tol_mm, double turn_rad,
                                                double pause_s) const {
  const double k = corner_moment_s(pause_s) * std::sin(turn_rad);
  return k > 0.0 ? tol_mm / k : std::numeric_limits<double>::infinity();
}

double FilterMoments::shortest_pause_s(double tol_mm, double turn_rad, double speed_mm_s) const {
  if (corner_error_mm(speed_mm_s, turn_rad, 0.0) <= tol_mm) return 0.0;
  double lo = 0.0, hi = static_cast<double>(order()) * period_s_;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (corner_error_mm(speed_mm_s, turn_rad, mid) > tol_mm)
      lo = mid;
    else
      hi = mid;
  }
  return hi;
}

}  // namespace gm
