// Test helper: a Pipeline one sample at a time (a one-row block), contour measured per sample.
#pragma once

#include "measure/contour_meter.hpp"
#include "motion/sample_block.hpp"
#include "motion/sample_record.hpp"
#include "pipeline/pipeline.hpp"

#include <cstdint>
#include <memory>
#include <span>

namespace gmtest {

/// Steps `Pipeline` as a real-time loop would, one sample per step(): command_n, then stages_n
/// over that one row, the row as a SampleRecord, its contour measured (unless `measure` is
/// false: then the contour fields are left for a ContourMeter from contour_meter(), fed every
/// record with started_motions()). Run's block loop gives the same samples.
class SampleStepper {
 public:
  SampleStepper(const gm::RunConfig& cfg, gm::CanonSource& source, bool measure = true)
      : pipeline_(cfg, source),
        meter_(pipeline_.contour_meter()),
        measure_(measure),
        period_s_(cfg.machine.period_s),
        step_(gm::with_axis_count(cfg.machine.axis_count(), [](auto n) {
          return &SampleStepper::step_n<decltype(n)::value>;
        })) {}

  /// Advances one period T with override `ovr` and fills `out`; when the status is not Working
  /// no sample was produced and `out` is left as it was. Only entries 0..N-1 of `out`'s per-axis
  /// vectors are written (N: the machine's axis count).
  gm::PipelineStatus step(const gm::OverrideInput& ovr, gm::SampleRecord& out) {
    return (this->*step_)(ovr, out);
  }
  /// The motion blocks that became current in the last step(), in order.
  std::span<const gm::Motion> started_motions() const { return one_->motions; }
  /// The last of them, nullptr if none started.
  const gm::Motion* started_motion() const {
    return one_->motions.empty() ? nullptr : &one_->motions.back();
  }
  /// A new meter set up for the pipeline's machine, filter and servo lag.
  gm::ContourMeter contour_meter() const { return pipeline_.contour_meter(); }
  /// Programmed end point of the last motion block (BLU, rounded once).
  const gm::AxisBlu& program_end_blu() const { return pipeline_.program_end_blu(); }
  const gm::Pipeline& pipeline() const { return pipeline_; }

 private:
  template <int N>
  gm::PipelineStatus step_n(const gm::OverrideInput& ovr, gm::SampleRecord& out) {
    one_->reset(k_);
    gm::PipelineStatus st = pipeline_.command_n<N>(ovr, *one_);
    if (st == gm::PipelineStatus::Flush) st = pipeline_.command_n<N>(ovr, *one_);  // not reached
    if (st != gm::PipelineStatus::Working) return st;
    pipeline_.stages_n<N>(*one_, 0, 1);
    one_->template record<N>(0, period_s_, out);
    ++k_;
    if (measure_) meter_.measure(out, one_->motions);
    return gm::PipelineStatus::Working;
  }

  gm::Pipeline pipeline_;
  gm::ContourMeter meter_;
  bool measure_;
  double period_s_;
  std::unique_ptr<gm::SampleBlock> one_ = std::make_unique<gm::SampleBlock>();
  std::int64_t k_ = 0;
  gm::PipelineStatus (SampleStepper::*step_)(const gm::OverrideInput&, gm::SampleRecord&);
};

}  // namespace gmtest
