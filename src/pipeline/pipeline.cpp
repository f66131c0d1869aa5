// Joins interpolator, Acc/Dec, servo and contour measurement: rows commanded, then staged.
#include "pipeline/pipeline.hpp"

#include "common/status.hpp"
#include "planner/servo_response.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace gm {
namespace {

InterpolatorConfig interpolator_config(const Machine& m, const Taps& taps, int settle_samples,
                                       const std::vector<double>& planned_weights) {
  InterpolatorConfig c;
  c.period_s = m.period_s;
  c.axes = m.layout;
  c.blu_mm = m.blu_mm();
  c.rapid_mm_min = m.rapid_mm_min;
  c.settle_samples = settle_samples;
  c.spindle_accel_rpm_s = m.spindle_accel_rpm_s;
  c.start_mm = AxisVec::Zero();
  // Pre-compensated arcs follow the rule of the weights planned for (only arcs the planner
  // marks use it): the FIR's, or the FIR and servo chain's.
  std::vector<double> h = planned_weights;
  if (h.empty())
    for (auto b : taps.integer) h.push_back(static_cast<double>(b) / static_cast<double>(taps.b_s));
  c.arc_comp = ArcCompensation(h, m.period_s);
  return c;
}

// The longest Acc/Dec filter of the machine, in samples: the machine's [accdec] and any axis's
// own (an exact stop waits for the longest to drain).
int longest_filter(const Machine& m, const Taps& taps) {
  auto n = static_cast<int>(taps.integer.size());
  for (int a = 0; a < m.axis_count(); ++a) {
    const AxisConfig& c = m.axes[static_cast<std::size_t>(a)];
    if (!c.accdec_profile.empty() || c.accdec_tau_s > 0.0)
      n = std::max(n, static_cast<int>(
                          design_taps(c.accdec_profile.empty() ? m.profile : c.accdec_profile,
                                      c.accdec_tau_s > 0.0 ? c.accdec_tau_s : m.tau_s, m.period_s)
                              .integer.size()));
  }
  return n;
}

// Samples the servo needs to close most of a step: five position-loop time constants.
std::int64_t servo_lag_samples(const Machine& m) {
  double kp = std::numeric_limits<double>::infinity();
  for (const auto& a : m.axes) kp = std::min(kp, a.kp_1_s);
  return static_cast<std::int64_t>(std::ceil(5.0 / kp / m.period_s));
}

}  // namespace

Pipeline::Pipeline(const RunConfig& cfg, CanonSource& source)
    : cfg_(cfg),
      taps_(design_taps(cfg.machine.profile, cfg.machine.tau_s, cfg.machine.period_s)),
      interp_(
          interpolator_config(cfg.machine, taps_,
                              std::max(longest_filter(cfg.machine, taps_), cfg.stop_hold_samples),
                              cfg.planned_weights),
          source),
      accdec_(taps_, AxisBlu::Zero(), FirStructure::Auto, cfg.machine.axis_count()),
      axes_(cfg.machine.axis_count()),
      match_(taps_, design_servo_match(cfg.machine, cfg.servo).taps),
      lag_samples_(static_cast<std::int64_t>(taps_.integer.size()) + match_.length() +
                   (cfg.servo ? servo_lag_samples(cfg.machine) : 0)),
      in_blu_(AxisBlu::Zero()),
      ref_blu_(AxisBlu::Zero()),
      last_cmd_blu_(AxisBlu::Zero()) {
  if (cfg_.servo)
    servo_.emplace(cfg_.machine, axes_, cfg_.machine.period_s, cfg_.machine.servo_substeps);
  modes_ = cfg_.servo && cfg_.machine.has_modes();
  // Axes with their own Acc/Dec (past X, Y, Z; machine_file.cpp refuses it for the path axes):
  // a one-axis filter each, whose output replaces the shared filter's for that axis.
  for (int a = 0; a < axes_; ++a) {
    const AxisConfig& c = cfg_.machine.axes[static_cast<std::size_t>(a)];
    if (c.accdec_profile.empty() && !(c.accdec_tau_s > 0.0)) continue;
    const Taps t = design_taps(c.accdec_profile.empty() ? cfg_.machine.profile : c.accdec_profile,
                               c.accdec_tau_s > 0.0 ? c.accdec_tau_s : cfg_.machine.tau_s,
                               cfg_.machine.period_s);
    own_accdec_.push_back({a, FirAccDec(t, AxisBlu::Zero(), FirStructure::Auto, 1)});
  }
  cmd_.pos_blu = AxisBlu::Zero();
}

void Pipeline::own_accdec_rows(SampleBlock& b, int first, int count) {
  for (OwnAccDec& o : own_accdec_)
    for (int i = first; i < first + count; ++i) {
      one_in_blu_[0] = b.cmd_blu.v[o.axis][i];
      o.fir.step_n<1>(one_in_blu_, one_out_blu_);
      b.ref_blu.v[o.axis][i] = one_out_blu_[0];
    }
}

ContourMeter Pipeline::contour_meter() const {
  // A block counts as steady, and a past block stops being a candidate, after the same delay.
  return ContourMeter(cfg_.machine.blu_mm(), cfg_.machine.layout, cfg_.machine.contour_blu_mm(),
                      lag_samples_, lag_samples_);
}

bool Pipeline::settled() const {
  if (!accdec_.settled()) return false;
  for (const OwnAccDec& o : own_accdec_)
    if (!o.fir.settled()) return false;
  if (!match_.settled()) return false;
  if (!cfg_.servo) return true;
  return quiet_samples_ >= kSettleQuietSamples;
}

template <int N>
PipelineStatus Pipeline::command_n(const OverrideInput& ovr, SampleBlock& b) {
  started_ = {};
  if (!program_done_) {
    if (interp_.step(ovr, cmd_) == InterpStatus::Finished) {
      program_done_ = true;
      done_k_ = k_;
    } else {
      last_cmd_blu_.head<N>() = cmd_.pos_blu.head<N>();
      if (cmd_.block_seq != seen_block_) {
        seen_block_ = cmd_.block_seq;
        started_ = interp_.started_motions();
      }
    }
  }
  if (program_done_) {
    if (unstaged_ > 0) return PipelineStatus::Flush;
    if (settled()) return PipelineStatus::Finished;
    if (static_cast<double>(k_ - done_k_) * cfg_.machine.period_s > cfg_.settle_timeout_s)
      return PipelineStatus::Unsettled;
  }
  // After the end the command stays where the last sample left it.
  const int i = b.count;
  for (int a = 0; a < N; ++a) b.cmd_blu.v[a][i] = cmd_.pos_blu[a];
  b.line[i] = cmd_.line;
  b.events[i] = program_done_ ? 0u : cmd_.events;
  b.feed_scale[i] = cmd_.feed_scale;
  b.settling[i] = program_done_;
  for (const Motion& m : started_) {
    b.motions.push_back(m);
    b.motion_row.push_back(i);
  }
  ++b.count;
  ++unstaged_;
  ++k_;
  return PipelineStatus::Working;
}

template <int N>
int Pipeline::command_span_n(const OverrideInput& ovr, SampleBlock& b, int max) {
  if (program_done_) return 0;
  const int i0 = b.count;
  const int n = interp_.span(ovr, std::min(max, kBlockSamples - i0), b.cmd_blu, i0, cmd_);
  started_ = {};
  for (int i = i0; i < i0 + n; ++i) {
    b.line[i] = cmd_.line;
    b.events[i] = 0u;
    b.feed_scale[i] = cmd_.feed_scale;
    b.settling[i] = false;
  }
  if (n > 0) last_cmd_blu_.head<N>() = cmd_.pos_blu.head<N>();
  b.count += n;
  unstaged_ += n;
  k_ += n;
  return n;
}

template <int N>
inline void Pipeline::accdec_row(SampleBlock& b, int i) {
  for (int a = 0; a < N; ++a) in_blu_[a] = b.cmd_blu.v[a][i];
  accdec_.step_n<N>(in_blu_, ref_blu_);
  for (int a = 0; a < N; ++a) b.ref_blu.v[a][i] = ref_blu_[a];
}

template <int N>
void Pipeline::stages_n(SampleBlock& b, int first, int count) {
  // Acc/Dec over the rows, then the servo over them. A block from its first row runs the
  // filter's block kernel; rows after a partial block (settling, step()) one at a time.
  if (first == 0)
    accdec_.step_block<N>(b.cmd_blu, b.ref_blu, count);
  else
    for (int i = first; i < first + count; ++i) accdec_row<N>(b, i);
  if (!own_accdec_.empty()) [[unlikely]]
    own_accdec_rows(b, first, count);
  if (!match_.empty()) [[unlikely]]
    match_.apply(b.cmd_blu, b.ref_blu, first, count);
  if (cfg_.servo) {
    const int done = servo_->step_block<N>(b.ref_blu, b.enc_blu, b.table_blu, first, count,
                                           modes_ ? &b.defl_blu : nullptr);
    if (done < count) {
      const int i = first + done;
      b.count = i;  // the rows before the divergence are complete
      unstaged_ = 0;
      throw InputError(fmt::format("axis {} at t = {:.3f} s (line {}): {}",
                                   cfg_.machine.layout.letter(servo_->diverged_axis()),
                                   static_cast<double>(b.k0 + i) * cfg_.machine.period_s, b.line[i],
                                   servo_->divergence()));
    }
    // The motor hunts inside one count at standstill (quantised feedback), so settling is
    // judged on the encoder alone: within ±1 count of the reference.
    quiet_samples_ = servo_->quiet_run();
  } else {
    for (int a = 0; a < N; ++a)
      for (int i = first; i < first + count; ++i) {
        b.enc_blu.v[a][i] = b.ref_blu.v[a][i];
        b.table_blu.v[a][i] = static_cast<double>(b.ref_blu.v[a][i]);
      }
  }
  unstaged_ -= count;
}

#define GM_PIPELINE_STEP_N(N)                                                                  \
  template PipelineStatus Pipeline::command_n<N>(const OverrideInput& ovr, SampleBlock& b);    \
  template int Pipeline::command_span_n<N>(const OverrideInput& ovr, SampleBlock& b, int max); \
  template void Pipeline::stages_n<N>(SampleBlock & b, int first, int count);
GM_FOR_EACH_AXIS_COUNT(GM_PIPELINE_STEP_N)
#undef GM_PIPELINE_STEP_N

}  // namespace gm
