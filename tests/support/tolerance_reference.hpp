// Test reference model: ToleranceCheck one SampleRecord at a time, with the motion it started.
#pragma once

#include "measure/tolerance_check.hpp"
#include "motion/canon.hpp"
#include "motion/sample_record.hpp"

namespace gmtest {

/// A ToleranceCheck fed one record at a time by add(), as a per-sample loop would: the reference
/// ToleranceCheck::add_block (the run's block form) must equal.
class ToleranceReference : public gm::ToleranceCheck {
 public:
  using gm::ToleranceCheck::ToleranceCheck;

  /// Judges record `r`; `started`: the last motion that became current in it, or nullptr.
  void add(const gm::SampleRecord& r, const gm::Motion* started) {
    if (started != nullptr) start(*started);
    if (!(tol_mm_ > 0.0)) return;
    judge(r.contour_err_blu, r.line, [&] { return r.t_s; });
  }
};

}  // namespace gmtest
