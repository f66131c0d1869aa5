// ArcPrecompCheck: the isolated compensated arc and the ramp's transient, through the weights.
#include "planner/arc_precomp.hpp"

#include <algorithm>
#include <cmath>

namespace gm {

ArcPrecompCheck::ArcPrecompCheck(const std::vector<double>& weights, double period_s)
    : h_(weights), period_s_(period_s), rule_(weights, period_s) {
  ring_.resize(h_.size());
  ring_p_.resize(h_.size());
}

double ArcPrecompCheck::speed_limit_mm_s(double sweep_abs_rad, double length_mm) const {
  if (!enabled() || !(sweep_abs_rad > 0.0)) return 0.0;
  return rule_.limit_omega_t() / period_s_ * length_mm / sweep_abs_rad;
}

Eigen::Vector2d ArcPrecompCheck::point(double p) const {
  if (p <= 0.0) return {p, 0.0};
  if (p < lp_) return {r_ * std::sin(p / r_), r_ - r_ * std::cos(p / r_)};
  const double th = lp_ / r_, d = p - lp_;
  return {r_ * std::sin(th) + d * std::cos(th), r_ - r_ * std::cos(th) + d * std::sin(th)};
}

double ArcPrecompCheck::run_segment(double p_from, double p_to, double phase, Start start,
                                    End end) const {
  const std::size_t n = h_.size();
  double worst = 0.0;
  std::size_t count = 0, head = 0, at_end = 0;
  // From rest: n samples at the arc's start, then the interpolator's ramp from 0 to v.
  double p = start == Start::FromRest ? 0.0 : p_from - static_cast<double>(n) * dp_ + phase * dp_;
  double v = start == Start::FromRest ? 0.0 : v_;
  std::size_t rest = start == Start::FromRest ? n : 0;
  while (p <= p_to && at_end < n) {
    double c = c_;
    if (rest > 0) {
      --rest;
      c = 0.0;
    } else if (v < v_) {
      v = std::min(v_, v + dv_);
      p += q_ * v * period_s_;
      c = rule_.correction_mm(r_, v * q_ / r_);
    } else {
      p += dp_;  // a sample at speed v
    }
    if (end == End::Stop && p >= lp_) {  // the interpolator stops on the arc's end point
      p = lp_;
      ++at_end;
    }
    Eigen::Vector2d x = point(p);
    if (p > 0.0 && p < lp_) {
      const double w = ArcCompensation::blend(p / q_, len_, blend_);
      x += w * c * Eigen::Vector2d(std::sin(p / r_), -std::cos(p / r_));
    }
    head = head == 0 ? n - 1 : head - 1;  // newest at head, h_0 on it
    ring_[head] = x;
    ring_p_[head] = p;
    if (++count < n) continue;
    Eigen::Vector2d y = Eigen::Vector2d::Zero();
    double pbar = 0.0;
    for (std::size_t i = 0, j = head; i < n; ++i, j = j + 1 == n ? 0 : j + 1) {
      y += h_[i] * ring_[j];
      pbar += h_[i] * ring_p_[j];
    }
    worst = std::max(worst, (y - point(pbar)).norm());
  }
  return worst;
}

double ArcPrecompCheck::isolated_mm(double radius_mm, double sweep_abs_rad, double length_mm,
                                    double v_plan, double v, double phase) const {
  r_ = radius_mm;
  len_ = length_mm;
  lp_ = radius_mm * sweep_abs_rad;
  q_ = lp_ / length_mm;
  v_ = v;
  dv_ = rule_.speed_step_mm_s(v_plan);
  blend_ = rule_.blend_length_mm(length_mm, v_plan);
  c_ = rule_.correction_mm(radius_mm, v * sweep_abs_rad / length_mm);
  dp_ = q_ * v * period_s_;
  const double W = static_cast<double>(h_.size()) * dp_, lb = q_ * blend_;
  // Between moving tangent lines, from rest at its start, to rest at its end.
  if (lp_ <= 2.0 * (lb + 2.0 * W))
    return std::max({run_segment(-W, lp_ + 2.0 * W, phase, Start::Moving, End::Moving),
                     run_segment(0.0, lp_ + 2.0 * W, phase, Start::FromRest, End::Stop),
                     run_segment(0.0, lp_ + 2.0 * W, phase, Start::FromRest, End::Moving),
                     run_segment(-W, lp_ + 2.0 * W, phase, Start::Moving, End::Stop)});
  return std::max(
      {run_segment(-W, lb + 2.0 * W, phase, Start::Moving, End::Moving),
       run_segment(0.0, lb + 2.0 * W + v * static_cast<double>(h_.size()) * q_ * period_s_, phase,
                   Start::FromRest, End::Moving),
       run_segment(lp_ - lb - W, lp_ + 2.0 * W, phase, Start::Moving, End::Moving),
       run_segment(lp_ - lb - W, lp_ + 2.0 * W, phase, Start::Moving, End::Stop)});
}

double ArcPrecompCheck::ramp_mm(double radius_mm, double sweep_abs_rad, double length_mm,
                                double v_plan) const {
  const std::size_t n = h_.size();
  const double q = radius_mm * sweep_abs_rad / length_mm, r = radius_mm;
  const double dv = rule_.speed_step_mm_s(v_plan);
  const auto on_circle = [r](double p, double rad) {
    return Eigen::Vector2d(rad * std::sin(p / r), r - rad * std::cos(p / r));
  };
  // v_p for a window, down to rest, a window at rest, up to v_p, a window at v_p.
  const int ramp = rule_.ramp_samples();
  const int total = static_cast<int>(3 * n) + 2 * ramp + 2;
  double v = v_plan, p = 0.0, worst = 0.0;
  std::size_t count = 0, head = 0;
  for (int k = 0; k < total; ++k) {
    const int t = k - static_cast<int>(n);
    if (t >= 0 && t <= ramp)
      v = std::max(0.0, v - dv);
    else if (t > ramp + static_cast<int>(n))
      v = std::min(v_plan, v + dv);
    p += q * v * period_s_;
    head = head == 0 ? n - 1 : head - 1;
    ring_[head] = on_circle(p, r + rule_.correction_mm(r, v * sweep_abs_rad / length_mm));
    ring_p_[head] = p;
    if (++count < n) continue;
    Eigen::Vector2d y = Eigen::Vector2d::Zero();
    double pbar = 0.0;
    for (std::size_t i = 0, j = head; i < n; ++i, j = j + 1 == n ? 0 : j + 1) {
      y += h_[i] * ring_[j];
      pbar += h_[i] * ring_p_[j];
    }
    worst = std::max(worst, (y - on_circle(pbar, r)).norm());
  }
  return worst;
}

double ArcPrecompCheck::error_mm(double radius_mm, double sweep_abs_rad, double length_mm,
                                 double v_plan) const {
  double worst = 0.0;
  for (double f : {1.0, 0.6})
    worst =
        std::max(worst, isolated_mm(radius_mm, sweep_abs_rad, length_mm, v_plan, f * v_plan, 0.25));
  return worst + ramp_mm(radius_mm, sweep_abs_rad, length_mm, v_plan);
}

}  // namespace gm
