// ArcResidualTable: E(x, |θ|) of the pre-compensated arc per unit radius, nodes simulated on
// first use, bounded between them by log-bilinear interpolation and a margin.
#include "planner/arc_residual_table.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gm {

ArcResidualTable::ArcResidualTable(const ArcPrecompCheck& check, ArcPrecompCheck::Judging judging)
    : period_s_(check.rule().period_s()), judging_(judging) {
  if (!check.enabled()) return;
  const double log_step = std::log(kStep);
  inv_log_step_ = 1.0 / log_step;
  x_top_ = check.rule().limit_omega_t();
  nx_ = static_cast<std::size_t>(std::ceil(std::log(kRateRange) * inv_log_step_)) + 1;
  x0_ = x_top_ / std::pow(kStep, static_cast<double>(nx_ - 1));
  // The long regime at every rate of the grid: |θ| > 4(N + 1)·limit (ArcPrecompCheck's runs).
  th_top_ = 4.0 * static_cast<double>(check.window_samples()) * x_top_ * 1.001;
  nth_ = static_cast<std::size_t>(std::ceil(std::log(th_top_ / kMinSweep) * inv_log_step_)) + 1;
  log_g_.assign(nx_ * nth_, std::numeric_limits<double>::quiet_NaN());
  ramp_.assign(nx_, std::numeric_limits<double>::quiet_NaN());
  log_ramps_.assign(nx_, std::numeric_limits<double>::quiet_NaN());
}

double ArcResidualTable::row_ramp(const ArcPrecompCheck& check, std::size_t k, double x) const {
  double& ramp = ramp_[k];
  if (std::isnan(ramp)) {
    const ArcPrecompCheck::Judged judged(check, judging_);
    ramp = check.ramp_mm(1.0, 1.0, 1.0, x / period_s_);
  }
  return ramp;
}

bool ArcResidualTable::covers(double sweep_abs_rad, double length_mm, double v_plan) const {
  if (nx_ == 0 || !(length_mm > 0.0)) return false;
  const double x = rate(sweep_abs_rad, length_mm, v_plan);
  // x_top_·(1 + 1e-9): the arc at its speed limit, x recomputed from that speed.
  return x >= x0_ && x <= x_top_ * (1.0 + 1e-9) && sweep_abs_rad >= kMinSweep &&
         sweep_abs_rad >= kMinSamples * x;
}

double ArcResidualTable::log_g(const ArcPrecompCheck& check, std::size_t k, std::size_t j) const {
  double& g = log_g_[k * nth_ + j];
  if (std::isnan(g)) {
    const double x = x0_ * std::pow(kStep, static_cast<double>(k));
    const double th = kMinSweep * std::pow(kStep, static_cast<double>(j));
    // error_mm(1, θ, θ, x/T), its ramp term kept per row.
    const ArcPrecompCheck::Judged judged(check, judging_);
    const double e = check.isolated_worst_mm(1.0, th, th, x / period_s_) + row_ramp(check, k, x);
    g = std::log(std::max(e, 1e-300) / (x * x));
    ++filled_;
  }
  return g;
}

double ArcResidualTable::log_ramps(const ArcPrecompCheck& check, std::size_t k) const {
  double& g = log_ramps_[k];
  if (std::isnan(g)) {
    const double x = x0_ * std::pow(kStep, static_cast<double>(k));
    const ArcPrecompCheck::Judged judged(check, judging_);
    g = std::log(std::max(check.ramps_mm(1.0, 1.0, 1.0, x / period_s_), 1e-300) / (x * x));
    ++filled_;
  }
  return g;
}

double ArcResidualTable::rate(double sweep_abs_rad, double length_mm, double v_plan) const {
  return v_plan * sweep_abs_rad / length_mm * period_s_;
}

double ArcResidualTable::rate_index(double x) const {
  return std::clamp(std::log(x / x0_) * inv_log_step_, 0.0, static_cast<double>(nx_ - 1));
}

double ArcResidualTable::ramps_bound_mm(const ArcPrecompCheck& check, double radius_mm,
                                        double sweep_abs_rad, double length_mm,
                                        double v_plan) const {
  const double x = rate(sweep_abs_rad, length_mm, v_plan), fx = rate_index(x);
  const std::size_t k = std::min(static_cast<std::size_t>(fx), nx_ - 2);
  const double tx = fx - static_cast<double>(k);
  const double lg = (1.0 - tx) * log_ramps(check, k) + tx * log_ramps(check, k + 1);
  return radius_mm * x * x * std::exp(lg) * (1.0 + kMargin);
}

double ArcResidualTable::error_bound_mm(const ArcPrecompCheck& check, double radius_mm,
                                        double sweep_abs_rad, double length_mm,
                                        double v_plan) const {
  const double x = rate(sweep_abs_rad, length_mm, v_plan), fx = rate_index(x);
  const double fth = std::clamp(std::log(sweep_abs_rad / kMinSweep) * inv_log_step_, 0.0,
                                static_cast<double>(nth_ - 1));
  const std::size_t k = std::min(static_cast<std::size_t>(fx), nx_ - 2);
  const std::size_t j = std::min(static_cast<std::size_t>(fth), nth_ - 2);
  const double tx = fx - static_cast<double>(k), tt = fth - static_cast<double>(j);
  const double lg = (1.0 - tx) * ((1.0 - tt) * log_g(check, k, j) + tt * log_g(check, k, j + 1)) +
                    tx * ((1.0 - tt) * log_g(check, k + 1, j) + tt * log_g(check, k + 1, j + 1));
  return radius_mm * x * x * std::exp(lg) * (1.0 + kMargin);
}

}  // namespace gm
