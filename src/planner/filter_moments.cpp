// FilterMoments: the corner moment D(P) by direct maximisation and by the symmetric closed form.
#include "planner/filter_moments.hpp"

#include "common/status.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gm {

FilterMoments::FilterMoments(const Taps& taps, double period_s) : period_s_(period_s) {
  if (taps.integer.empty() || taps.b_s <= 0) throw InputError("filter moments need taps");
  h_.reserve(taps.integer.size());
  for (auto b : taps.integer) h_.push_back(static_cast<double>(b) / static_cast<double>(taps.b_s));
  for (std::size_t i = 0; i < h_.size(); ++i) centre_ += static_cast<double>(i) * h_[i];
  for (std::size_t i = 0; i < h_.size(); ++i) {
    const double d = (static_cast<double>(i) - centre_) * period_s_;
    variance_s2_ += h_[i] * d * d;
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

double FilterMoments::corner_moment_s(double pause_s) const {
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
