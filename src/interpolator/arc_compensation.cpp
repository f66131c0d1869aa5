// ArcCompensation: the table of A(ωT), the rows and blend at an arc's ends and the speed ramp.
#include "interpolator/arc_compensation.hpp"

#include "accdec/taps.hpp"

#include <algorithm>
#include <cmath>

namespace gm {

ArcCompensation::ArcCompensation(const std::vector<double>& weights, double period_s, bool end_rows)
    : h_(weights), period_s_(period_s) {
  if (h_.empty() || !(period_s > 0.0)) return;
  double sum = 0.0;
  for (std::size_t i = 0; i < h_.size(); ++i) {
    centre_ += static_cast<double>(i) * h_[i];
    sum += h_[i];
  }
  // Symmetric about its centre over its support: a window lengthened by zero weights (the
  // S-curves' last tap, an overshooting chain's tail) is as symmetric as its support.
  symmetric_ = weights_symmetric(h_);
  const std::size_t first = weights_support(h_).first;
  if (std::abs(sum - 1.0) > 1e-9 || h_.size() < 2) return;
  // The first crossing of kMinGain: scanned in steps of π/(64·N), then bisected.
  const double step = std::acos(-1.0) / (64.0 * static_cast<double>(h_.size() - 1));
  double lo = 0.0, hi = step;
  while (gain_exact(hi) >= kMinGain) {
    lo = hi;
    hi += step;
    if (hi > std::acos(-1.0)) return;  // a filter that barely filters: nothing to do
  }
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (gain_exact(mid) >= kMinGain ? lo : hi) = mid;
  }
  limit_ = lo;
  inv_step_ = static_cast<double>(kTableSteps) / limit_;
  table_.resize(kTableSteps + 1);
  for (int k = 0; k <= kTableSteps; ++k)
    table_[static_cast<std::size_t>(k)] =
        gain_exact(limit_ * static_cast<double>(k) / static_cast<double>(kTableSteps));
  ratio_max_.resize(table_.size());
  double ratio = 0.0;
  for (std::size_t k = 0; k < table_.size(); ++k)
    ratio_max_[k] = ratio = std::max(ratio, std::abs(1.0 / table_[k] - 1.0) * (1.0 + 1e-9));
  ramp_samples_ = static_cast<int>(h_.size());
  if (!symmetric_) h_reversed_.assign(h_.rbegin(), h_.rend());
  rows_on_ = end_rows && h_[first] <= kTaper * *std::max_element(h_.begin(), h_.end()) &&
             h_.size() <= ArcEndRows::kMaxWindow;
}

double ArcCompensation::gain_exact(double omega_t) const {
  return weights_gain(h_, centre_, symmetric_, omega_t);
}

double ArcCompensation::blend_length_mm(double length_mm, double planned_mm_s) const {
  return std::min(0.5 * length_mm, kBlendSamples * period_s_ * planned_mm_s);
}

}  // namespace gm
