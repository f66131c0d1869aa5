// Test reference model: RunSummary's statistics one SampleRecord at a time, as plain arithmetic.
#pragma once

#include "interpolator/interpolator.hpp"
#include "measure/run_summary.hpp"
#include "motion/sample_record.hpp"

#include <cmath>
#include <cstdlib>

namespace gmtest {

/// A RunSummary fed one record at a time by add(): the statistics written out sample by sample,
/// the reference RunSummary::add_block (the run's block form, four rows a vector) must equal
/// bit for bit. text(), json() and finish() are RunSummary's own.
class SummaryReference : public gm::RunSummary {
 public:
  using gm::RunSummary::RunSummary;

  /// Adds one sample (every sample, not only the decimated trace rows).
  void add(const gm::SampleRecord& s) {
    const double T = period_s_;
    for (int a = 0; a < axes_; ++a) {
      gm::AxisSummary& ax = axes[static_cast<std::size_t>(a)];
      const double v = static_cast<double>(s.ref_blu[a] - prev_ref_[a]) * blu_mm_[a] / T;  // mm/s
      const double acc = (v - prev_v_[a]) / T;
      const double jerk = (acc - prev_a_[a]) / T;
      ax.following_err_blu.update(static_cast<double>(std::llabs(s.ferr_blu[a])), s.line);
      ax.velocity_mm_s.update(std::abs(v), s.line);
      ax.accel_mm_s2.update(std::abs(acc), s.line);
      ax.jerk_mm_s3.update(std::abs(jerk), s.line);
      // Eq. 26 with the paper's units: F = m·a + c·V in N (m/s, m/s²), P = F·V in W.
      const double v_m_s = v / 1000.0, a_m_s2 = acc / 1000.0;
      const double force = std::abs(mass_kg_[a] * a_m_s2 + damping_kg_s_[a] * v_m_s);
      const double power = std::abs(force * v_m_s);
      auto check = [&](gm::LimitCheck& c, double value) {
        c.worst.update(value, s.line);
        if (value > c.limit * (1 + 1e-9)) ++c.violations;
      };
      check(ax.v_limit, std::abs(v));
      check(ax.f_limit, force);
      check(ax.p_limit, power);
      prev_v_[a] = v;
      prev_a_[a] = acc;
      if (s.ref_blu[a] != prev_ref_[a]) last_motion_k_ = s.k;
    }
    prev_ref_ = s.ref_blu;
    contour_err_blu.update(std::abs(s.contour_err_blu), s.line);
    contour_sq_sum_ += s.contour_err_blu * s.contour_err_blu;
    if (!std::isnan(s.arc_ref_dev_blu)) {
      arc_ref_sum_ += s.arc_ref_dev_blu;
      arc_enc_sum_ += s.arc_enc_dev_blu;
      ++arc_samples;
    }
    if ((s.events & gm::kEventHold) != 0) ++hold_samples_;
    ++samples;
  }
};

}  // namespace gmtest
