// The whole pipeline, block by block: interpolator -> Acc/Dec -> servo -> encoder.
#pragma once

#include "accdec/fir_filter.hpp"
#include "accdec/taps.hpp"
#include "common/axis.hpp"
#include "interpolator/interpolator.hpp"
#include "machine/machine.hpp"
#include "measure/contour_meter.hpp"
#include "motion/canon.hpp"
#include "motion/sample_block.hpp"
#include "motion/sample_record.hpp"
#include "servo/servo_bank.hpp"
#include "servo/servo_match.hpp"

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
  /// Samples the interpolator holds at an exact stop, at least the longest Acc/Dec filter's:
  /// the chain the tolerance is planned for (FIR and servo with tolerance_on = encoder), which
  /// the planner counts as the rest at a stop (Run sets it).
  int stop_hold_samples = 0;
  /// The weights the tolerance is planned for (Run sets them): the chain's with tolerance_on =
  /// encoder, whose gain pre-compensated arcs are commanded for; empty: the FIR's.
  std::vector<double> planned_weights;
};

enum class PipelineStatus {
  Working,    ///< a sample was produced
  Finished,   ///< program ended and every axis settled; no sample produced
  Unsettled,  ///< program ended but the axes did not settle within settle_timeout_s
  /// command_n only: the program has ended and whether the axes have settled depends on the
  /// rows commanded but not staged yet. Run stages_n over them, then call command_n again.
  Flush
};

/// Owns the stages and runs them over blocks of samples. Nothing is allocated per sample.
///
/// The block engine, two calls (gmotion run's loop is src/pipeline/run.cpp):
///   - command_n(ovr, block) interpolates one more row of `block` (the override may change from
///     sample to sample, and the schedule can depend on the previous row's line);
///   - stages_n(block, first, count) runs Acc/Dec and servo over rows first .. first+count-1,
///     stage after stage.
/// Once the program has ended, each settling row needs the stages of the rows before it
/// (whether the axes have settled), so command_n asks for them (Flush) and the caller then takes
/// one row at a time. The contour is measured by the caller (a ContourMeter from contour_meter()
/// over the staged rows: Run does it with the outputs).
class Pipeline {
 public:
  /// `source` is pulled as the interpolator needs blocks. Throws gm::InputError on a bad
  /// machine (profile spec, τ not a multiple of T, ...).
  Pipeline(const RunConfig& cfg, CanonSource& source);

  /// Interpolates row b.count of `b` (sample index k0 + count) with override `ovr` and counts it
  /// (Working); or, once the program has ended, a settling row, Finished, Unsettled, or Flush
  /// (nothing done). `b` must not be full; the rows before it are the previous samples.
  template <int N>
  PipelineStatus command_n(const OverrideInput& ovr, SampleBlock& b);
  /// Interpolates up to `max` more rows of `b` (from row b.count) with override `ovr` while
  /// nothing but the position changes (Interpolator::span); returns how many (0: use
  /// command_n). The caller guarantees the override stays `ovr` for those samples.
  template <int N>
  int command_span_n(const OverrideInput& ovr, SampleBlock& b, int max);
  /// Acc/Dec and servo over rows first .. first+count-1 of `b`, commanded by command_n and not
  /// staged yet, in order. Throws gm::InputError when the servo diverges, after setting b.count
  /// to the row it diverged in (the rows before it are complete).
  template <int N>
  void stages_n(SampleBlock& b, int first, int count);
  /// The program has ended: the rows from now on are settling rows.
  bool program_done() const { return program_done_; }

  const Taps& taps() const { return taps_; }
  const Machine& machine() const { return cfg_.machine; }
  /// Programmed end point of the last motion block (BLU, rounded once).
  const AxisBlu& program_end_blu() const { return last_cmd_blu_; }
  /// A new meter set up for this pipeline's machine, filter and servo lag: feed it the staged
  /// rows (ContourMeter::measure_block) to fill their contour columns.
  ContourMeter contour_meter() const;

 private:
  bool settled() const;
  /// Acc/Dec for one row.
  template <int N>
  void accdec_row(SampleBlock& b, int i);
  /// The axes with their own Acc/Dec, rows first.. of `b`: their filters' outputs replace the
  /// shared one's (out of line, so that the common path stays as it was).
  [[gnu::noinline]] void own_accdec_rows(SampleBlock& b, int first, int count);

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
  std::optional<ServoBank> servo_;  ///< every axis's servo (with cfg_.servo)
  ServoMatch match_;    ///< the servos' references matched to the planned chain's (servo_matching)
  bool modes_ = false;  ///< the servo runs structural modes: the block gets their deflection
  std::int64_t lag_samples_;  ///< Acc/Dec length + servo lag: how long a past block can be nearest
  CommandSample cmd_{};
  AxisBlu in_blu_, ref_blu_, last_cmd_blu_;
  int unstaged_ = 0;  ///< rows commanded and not yet staged
  std::int64_t k_ = 0;
  std::uint64_t seen_block_ = 0;
  std::span<const Motion> started_;  ///< the motions that became current in the last row
  bool program_done_ = false;
  std::int64_t done_k_ = 0;
  int quiet_samples_ = 0;
  /// Samples in a row with every axis still (ServoBank::quiet_run) before the servos count as
  /// settled.
  static constexpr int kSettleQuietSamples = 25;
};

}  // namespace gm
