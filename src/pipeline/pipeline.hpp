// The whole pipeline, one sample at a time: interpolator -> Acc/Dec -> servo -> encoder.
#pragma once

#include "accdec/fir_filter.hpp"
#include "accdec/taps.hpp"
#include "common/axis.hpp"
#include "interp/canon.hpp"
#include "interpolator/interpolator.hpp"
#include "machine/machine.hpp"
#include "pipeline/path_window.hpp"
#include "pipeline/sample_record.hpp"
#include "servo/servo_axis.hpp"

#include <array>
#include <cstdint>
#include <optional>

namespace gm {

/// What a run needs besides the program: the machine (flags already applied) and the switches.
struct RunConfig {
  Machine machine;
  bool servo = true;                 ///< false: ideal axes, the encoder reads the Acc/Dec output
  double settle_timeout_s = 10.0;    ///< after the program ends, how long the axes may take to settle
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

  /// Advances one interpolation period T with override `ovr` and fills `out`.
  PipelineStatus step(const OverrideInput& ovr, SampleRecord& out);

  const Taps& taps() const { return taps_; }
  const Machine& machine() const { return cfg_.machine; }
  /// Programmed end point of the last motion block (BLU, rounded once).
  const AxisBlu& program_end_blu() const { return last_cmd_blu_; }

 private:
  bool settled() const;

  RunConfig cfg_;
  AxisVec blu_mm_;
  double contour_blu_mm_;  ///< the BLU contour error is expressed in (smallest axis BLU)
  Taps taps_;
  Interpolator interp_;
  FirAccDec accdec_;
  std::array<std::optional<ServoAxis>, kAxes> servo_;
  PathWindow window_;
  CommandSample cmd_{};
  AxisBlu ref_blu_, enc_blu_, last_cmd_blu_;
  AxisVec table_blu_ = AxisVec::Zero();  ///< table positions (BLU, continuous) at the sample instant
  std::int64_t k_ = 0;
  std::uint64_t seen_block_ = 0;
  std::int64_t block_start_k_ = 0;
  std::int64_t last_pause_k_ = -1;  ///< last sample the interpolator was not moving
  std::int64_t steady_after_ = 0;  ///< samples after a block start before it counts as steady
  bool program_done_ = false;
  std::int64_t done_k_ = 0;
  int quiet_samples_ = 0;
};

}  // namespace gm
