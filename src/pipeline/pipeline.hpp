// The whole pipeline, one sample at a time: interpolator -> Acc/Dec -> servo -> encoder.
#pragma once

#include "accdec/fir_filter.hpp"
#include "accdec/taps.hpp"
#include "common/axis.hpp"
#include "interp/canon.hpp"
#include "interpolator/interpolator.hpp"
#include "machine/machine.hpp"
#include "pipeline/contour_meter.hpp"
#include "pipeline/sample_record.hpp"
#include "servo/servo_axis.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace gm {

/// What a run needs besides the program: the machine (flags already applied) and the switches.
struct RunConfig {
  Machine machine;
  bool servo = true;               ///< false: ideal axes, the encoder reads the Acc/Dec output
  double settle_timeout_s = 10.0;  ///< after the program ends, how long the axes may take to settle
  /// false: step() measures the contour error itself. true: step() leaves contour_err_blu and
  /// arc_*_dev_blu for a ContourMeter from contour_meter() fed every record with
  /// started_motions(), e.g. on another thread (the same values, measured elsewhere).
  bool defer_contour = false;
};

enum class PipelineStatus {
  Working,   ///< a sample was produced
  Finished,  ///< program ended and every axis settled; no sample produced
  Unsettled  ///< program ended but the axes did not settle within settle_timeout_s
};

/// Owns the stages and steps them together. Nothing is allocated per sample.
class Pipeline {
 public:
  /// `source` is pulled as the interpolator needs blocks. Throws gm::InputError on a bad
  /// machine (profile spec, τ not a multiple of T, ...).
  Pipeline(const RunConfig& cfg, CanonSource& source);

  /// Advances one interpolation period T with override `ovr` and fills `out`; when the status
  /// is not Working no sample was produced and `out` is left as it was.
  PipelineStatus step(const OverrideInput& ovr, SampleRecord& out) {
    return (this->*step_)(ovr, out);
  }
  /// step() for a machine of exactly N axes (axis_count()): every per-axis loop has a
  /// compile-time trip count; only entries 0..N-1 of `out`'s vectors are written (the rest
  /// keep what they had: 0 in a fresh record). Instantiated for GM_FOR_EACH_AXIS_COUNT.
  template <int N>
  PipelineStatus step_n(const OverrideInput& ovr, SampleRecord& out);

  const Taps& taps() const { return taps_; }
  const Machine& machine() const { return cfg_.machine; }
  /// Programmed end point of the last motion block (BLU, rounded once).
  const AxisBlu& program_end_blu() const { return last_cmd_blu_; }
  /// The motion blocks that became current in the last step(), in order (several when blocks
  /// are shorter than a sample's travel); empty if none did. Valid until the next step().
  std::span<const Motion> started_motions() const { return started_; }
  /// The last of them (the block the sample ends in), nullptr if none started.
  const Motion* started_motion() const { return started_.empty() ? nullptr : &started_.back(); }
  /// A new meter set up for this pipeline's machine, filter and servo lag: with defer_contour,
  /// feed it every record of step() with started_motions() to complete the records.
  ContourMeter contour_meter() const;

 private:
  bool settled() const;
  /// The axes with their own Acc/Dec: their filters' outputs replace the shared one's (out of
  /// line, so that the common path stays as it was).
  [[gnu::noinline]] void step_own_accdec();

  RunConfig cfg_;
  Taps taps_;
  Interpolator interp_;
  FirAccDec accdec_;
  /// An axis with its own Acc/Dec (AxisConfig::accdec_profile / accdec_tau_s) and its filter.
  struct OwnAccDec {
    int axis;
    FirAccDec fir;
  };
  std::vector<OwnAccDec> own_accdec_;
  AxisBlu one_in_blu_ = AxisBlu::Zero(), one_out_blu_ = AxisBlu::Zero();
  int axes_;  ///< the machine's axis count (entries 0..axes_-1 of the per-axis vectors)
  std::array<std::optional<ServoAxis>, kMaxAxes> servo_;
  std::int64_t lag_samples_;  ///< Acc/Dec length + servo lag: how long a past block can be nearest
  ContourMeter meter_;        ///< used unless defer_contour
  CommandSample cmd_{};
  AxisBlu ref_blu_, enc_blu_, last_cmd_blu_;
  MachineVec table_blu_ =
      MachineVec::Zero();  ///< table positions (BLU, continuous) at the sample instant
  std::int64_t k_ = 0;
  std::uint64_t seen_block_ = 0;
  std::span<const Motion> started_;
  bool program_done_ = false;
  std::int64_t done_k_ = 0;
  int quiet_samples_ = 0;
  /// step_n for the machine's axis count, chosen once in the constructor.
  PipelineStatus (Pipeline::*step_)(const OverrideInput&, SampleRecord&) = nullptr;
};

}  // namespace gm
