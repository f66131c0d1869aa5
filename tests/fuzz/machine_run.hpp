// What a run builds from a machine a fuzz target accepted: taps, then a bounded pipeline run.
#pragma once

#include "accdec/taps.hpp"
#include "common/status.hpp"
#include "machine/machine.hpp"
#include "motion/canon.hpp"
#include "pipeline/pipeline.hpp"
#include "support/sample_stepper.hpp"

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace fuzz {

/// A fixed list of canonical commands (no interpreter involved).
class ListSource : public gm::CanonSource {
 public:
  explicit ListSource(std::vector<gm::Canon> items) : items_(std::move(items)) {}
  bool next(gm::Canon& out) override {
    if (next_ >= items_.size()) return false;
    out = items_[next_++];
    return true;
  }

 private:
  std::vector<gm::Canon> items_;
  std::size_t next_ = 0;
};

/// Steps a pipeline until it finishes or `max_steps` samples have passed.
inline void run_pipeline(const gm::Machine& m, bool servo, std::vector<gm::Canon> program,
                         int max_steps) {
  gm::RunConfig cfg{m, servo, 1.0, 0, {}};
  ListSource source(std::move(program));
  gmtest::SampleStepper pipeline(cfg, source);
  gm::SampleRecord rec;
  for (int i = 0; i < max_steps; ++i)
    if (pipeline.step(gm::OverrideInput{}, rec) != gm::PipelineStatus::Working) break;
}

/// Taps × axes × samples one input may run by default (about 0.1 s under the sanitizers).
inline constexpr std::size_t kTapSampleBudget = 2'000'000;

/// The taps, then the pipeline (interpolator, Acc/Dec, servo axes, contour window): servo on
/// with no motion, servo off along a 0.5 mm line on every axis. A tap design the reader let
/// through may still be refused with gm::InputError (e.g. tau not a whole number of periods):
/// a run reports it the same way, so it is not a failure here.
inline void run_machine(const gm::Machine& m, std::size_t budget = kTapSampleBudget) {
  try {
    const gm::Taps taps = gm::design_taps(m.profile, m.tau_s, m.period_s);
    // A sample costs a multiply per tap and axis: a 23,000-tap filter (tau 9.2 s at T 0.4 ms)
    // took 9 s of the 10 s timeout under the sanitizers for 4,096 samples. The work an input
    // may ask is bounded instead (at least 4 samples: each runs every stage).
    const std::size_t per_sample = taps.integer.size() * static_cast<std::size_t>(m.axis_count());
    const int steps = static_cast<int>(
        std::clamp<std::size_t>(budget / std::max<std::size_t>(per_sample, 1), 4, 4096));
    run_pipeline(m, true, {}, steps);
    gm::Motion line;
    line.line = 1;
    line.end_mm = gm::AxisVec::Constant(0.5);
    line.feed_mm_min = 600.0;
    run_pipeline(m, false, {gm::Canon{line}}, steps);
  } catch (const gm::InputError&) {
  }
}

}  // namespace fuzz
