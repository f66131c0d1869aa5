// The run loop: overrides in, one pipeline step, stop rules, outputs out; one sample per step().
#include "pipeline/run.hpp"

#include "common/status.hpp"
#include "override/live_override.hpp"
#include "override/override_recorder.hpp"
#include "pipeline/sample_queue.hpp"
#include "planner/servo_response.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <exception>
#include <string>
#include <thread>

namespace gm {

namespace {

// The interpreter options for the run's stream: the run's machine (which outlives the stream),
// and the lines read ahead on a thread of their own when the run has its consumer thread (two
// cores, not in real time: a real-time step still reads and parses its own block).
InterpreterOptions stream_options(InterpreterOptions opts, const RunOptions& o) {
  opts.machine = &o.config.machine;
  opts.read_ahead = o.consumer_thread;
  return opts;
}

bool realtime(const RunOptions& o) {
  return o.live_fd >= 0;
}

// The consumer thread is worth it only with a second core, and never paces a real-time run.
RunOptions with_thread_choice(RunOptions o) {
  o.consumer_thread = o.consumer_thread && !realtime(o) && std::thread::hardware_concurrency() >= 2;
  return o;
}

// The tolerance planner over `source` for the machine's filter and overrides (G64 P).
// One BLU over the tolerance is allowed when it is planned for the table (tolerance_on = encoder).
double encoder_allowance_mm(const RunConfig& c) {
  return c.servo && c.machine.tolerance_on == ToleranceOn::Encoder ? c.machine.contour_blu_mm()
                                                                   : 0.0;
}

// With tolerance_on = encoder and the servo on, the chain is FIR + servo (planner/servo_response);
// the interpolator holds an exact stop for the whole chain (`run`'s stop_hold_samples), as the
// planner counts it.
std::unique_ptr<TolerancePlanner> make_planner(RunConfig& run, CanonSource& source) {
  const Machine& m = run.machine;
  PlannerConfig c;
  c.max_override = m.max_override;
  c.rapid_mm_min = m.rapid_mm_min;
  const PlannedChain chain = plan_chain(m, run.servo);
  c.speed_error_s = chain.speed_error_s;
  c.step_error = chain.step_error;
  c.drive_speed_mm_s = chain.drive_speed_mm_s;
  run.stop_hold_samples = static_cast<int>(chain.weights.size());
  run.planned_weights = chain.weights;
  if (c.speed_error_s > 0.0) c.fir_variation = fir_variation(m);
  const FilterMoments moments(chain.weights, m.period_s);
  c.rounding_mm = m.xyz_blu_mm().norm() + chain.extra_margin_mm;
  c.precompensate_arcs = m.arc_precompensation;
  c.precompensate_g61_arcs = m.g61_arc_precompensation;
  c.private_arcs = m.private_arcs;
  return std::make_unique<TolerancePlanner>(moments, c, source);
}

}  // namespace

Run::Run(RunOptions options, CanonSource& source) : Run(std::move(options), &source, nullptr, {}) {}

Run::Run(RunOptions options, std::istream& program, InterpreterOptions opts)
    : Run(std::move(options), nullptr, &program, std::move(opts)) {}

Run::Run(RunOptions options, CanonSource* source, std::istream* program, InterpreterOptions opts)
    : options_(with_thread_choice(std::move(options))),
      stream_(program == nullptr ? nullptr
                                 : std::make_unique<ProgramStream>(*program, options_.program_name,
                                                                   stream_options(opts, options_))),
      planner_(make_planner(options_.config, source != nullptr ? *source : *stream_)),
      ahead_(options_.consumer_thread ? std::make_unique<CanonReadAhead>(*planner_) : nullptr),
      pipeline_(options_.config, ahead_ != nullptr ? static_cast<CanonSource&>(*ahead_)
                                                   : static_cast<CanonSource&>(*planner_)),
      summary_(options_.config.machine),
      tolerance_(options_.config.machine.contour_blu_mm(), encoder_allowance_mm(options_.config),
                 options_.config.machine.period_s),
      player_(options_.schedule, options_.config.machine.period_s, options_.feed_override_pct,
              options_.rapid_override_pct) {
  init();
}

TraceMeta Run::trace_meta() const {
  const RunOptions& o = options_;
  TraceMeta meta;
  meta.program = o.program_name;
  meta.machine_name = o.config.machine.name;
  meta.machine_source = o.config.machine.source;
  meta.profile = o.config.machine.profile;
  meta.taps = static_cast<int>(pipeline_.taps().integer.size());
  meta.tau_s = o.config.machine.tau_s;
  meta.period_s = o.config.machine.period_s;
  meta.axes = o.config.machine.layout.letters();
  meta.blu_mm = o.config.machine.blu_mm();
  meta.servo = o.config.servo;
  meta.decimate = o.decimate;
  if (o.config.servo && o.config.machine.has_modes()) meta.columns = kTraceModes;
  return meta;
}

void Run::init() {
  const RunOptions& o = options_;
  sinks_ = {&summary_, &tolerance_};
  if (o.config.servo && o.config.machine.has_modes())
    summary_.measure_vibration(static_cast<int>(pipeline_.taps().integer.size()));
  if (!o.trace_path.empty()) {
    TraceMeta meta = trace_meta();
    meta.status_line = o.keep_partial;
    trace_ = std::make_unique<TraceWriter>(o.trace_path, o.trace_format, meta);
    sinks_.push_back(trace_.get());
  }
  if (realtime(o)) {
    live_ = std::make_unique<LiveOverride>(o.live_fd, o.config.machine.max_override * 100.0);
    live_open_ = true;
  }
  if (!o.record_override_path.empty())
    recorder_ =
        std::make_unique<OverrideRecorder>(o.record_override_path, o.config.machine.period_s);
  realtime_ = realtime(o);
  // The contour is measured with the outputs, on the consumer's copy of each sample.
  meter_.emplace(pipeline_.contour_meter());
  fill_ = with_axis_count(o.config.machine.axis_count(),
                          [](auto n) { return &Run::fill_n<decltype(n)::value>; });
  consume_block_ = with_axis_count(o.config.machine.axis_count(),
                                   [](auto n) { return &Run::consume_rows<decltype(n)::value>; });
  if (o.consumer_thread)
    queue_ =
        std::make_unique<SampleQueue>([this](SampleBlock& b) { (this->*consume_block_)(b, 0); }, 0);
  else
    block_ = std::make_unique<SampleBlock>();
  t0_ = std::chrono::steady_clock::now();
  next_progress_ = t0_ + std::chrono::seconds(1);
}

Run::~Run() = default;

template <int N>
void Run::consume_rows(SampleBlock& b, int first) {
  if (first >= b.count) return;
  // Column by column: the contour of every row, then the outputs over them.
  meter_->measure_block(b, first);
  for (BlockSink* sink : sinks_) sink->consume(b, first);
  // Without the consumer thread last() is the consumed row, contour fields included.
  if (!queue_) {
    const int i = b.count - 1;
    b.record<N>(i, options_.config.machine.period_s, rec_);
    rec_.contour_err_blu = b.contour_err_blu[i];
    rec_.arc_ref_dev_blu = b.arc_ref_dev_blu[i];
    rec_.arc_enc_dev_blu = b.arc_enc_dev_blu[i];
  }
}

template <int N>
void Run::stage_rows(SampleBlock& b, int first) {
  try {
    pipeline_.stages_n<N>(b, first, b.count - first);
  } catch (const InputError&) {
    // The rows before the divergence (b.count now) are complete: they reach the outputs.
    if (!queue_) consume_rows<N>(b, first);
    throw;
  }
}

template <int N>
RunStatus Run::fill_n(int max_rows) {
  const RunOptions& o = options_;
  SampleBlock& b = queue_ ? queue_->block() : *block_;
  const int first = b.count;
  const int limit = std::min(kBlockSamples, first + max_rows);
  int staged = first;
  PipelineStatus st = PipelineStatus::Working;
  std::string stop;  // a stop rule's message: the row that broke it is not handed on
  while (b.count < limit) {
    player_.advance(k_, line_);
    if (live_open_) {
      double feed = player_.feed_percent(), rapid = player_.rapid_percent();
      live_open_ = live_->poll(feed, rapid);
      player_.set(feed, rapid);
    }
    ovr_.feed_scale = player_.feed_scale();
    ovr_.rapid_scale = player_.rapid_scale();
    if (recorder_) recorder_->sample(k_, player_.feed_percent(), player_.rapid_percent());
    st = pipeline_.command_n<N>(ovr_, b);
    if (st == PipelineStatus::Flush) {  // the program has ended: settling needs the stages
      stage_rows<N>(b, staged);
      staged = b.count;
      st = pipeline_.command_n<N>(ovr_, b);
    }
    if (st != PipelineStatus::Working) break;
    const int row = b.count - 1;
    ++k_;
    line_ = b.line[row];
    if (const StopRule rule = broken_rule(b, row); rule != StopRule::None) {
      stop = stop_message(rule, b, row);
      break;
    }
    if (realtime_)
      std::this_thread::sleep_until(
          t0_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                    std::chrono::duration<double>(static_cast<double>(b.k0 + row) *
                                                      o.config.machine.period_s +
                                                  o.config.machine.period_s)));
    if (pipeline_.program_done()) break;  // one settling row at a time
    // Inside a move, while the override stays as it is, the rows that follow need none of the
    // above per row: the interpolator runs them as one span. (The player has seen the line the
    // span stays on, so no line change can fire in it; the time changes bound it.)
    if (realtime_ || b.count == limit) continue;
    const int room = player_.steady_samples(k_, line_, limit - b.count);
    const int span = room > 0 ? pipeline_.command_span_n<N>(ovr_, b, room) : 0;
    if (span == 0) continue;
    const int r0 = b.count - span;
    k_ += span;
    // A rule broken in the span is broken first at its first row (an interrupt: as if the
    // signal came before the span) or at the first row past the time limit.
    if (broken_rule(b, b.count - 1) != StopRule::None) {
      int r = r0;
      StopRule rule = StopRule::None;
      while ((rule = broken_rule(b, r)) == StopRule::None) ++r;
      stop = stop_message(rule, b, r);
      b.count = r + 1;
      break;
    }
  }
  if (b.count > staged) stage_rows<N>(b, staged);
  if (b.count > first) b.record<N>(b.count - 1, o.config.machine.period_s, rec_);
  if (!stop.empty()) {
    --b.count;  // the row that broke the rule is not handed on
    if (!queue_) consume_rows<N>(b, first);
    throw InputError(stop);
  }
  if (queue_) {
    if (b.full()) queue_->next_block(k_);
  } else {
    consume_rows<N>(b, first);
    if (b.full()) b.reset(k_);
  }
  if (st != PipelineStatus::Working && st != PipelineStatus::Flush) {
    const RunStatus rs =
        st == PipelineStatus::Finished ? RunStatus::Finished : RunStatus::Unsettled;
    finish(rs);
    return rs;
  }
  if (o.progress && !realtime_ && ((b.k0 + first) >> 16) != (k_ >> 16) &&
      std::chrono::steady_clock::now() > next_progress_) {
    o.progress(rec_);
    progress_shown_ = true;
    next_progress_ += std::chrono::seconds(1);
  }
  return RunStatus::Working;
}

Run::StopRule Run::broken_rule(const SampleBlock& b, int row) const {
  const RunOptions& o = options_;
  if (o.interrupted != nullptr && *o.interrupted != 0) return StopRule::Interrupted;
  if (o.max_time_s > 0 &&
      static_cast<double>(b.k0 + row) * o.config.machine.period_s > o.max_time_s)
    return StopRule::MaxTime;
  if ((b.events[row] & kEventHold) != 0 && !live_open_ && !player_.may_change())
    return StopRule::Held;
  return StopRule::None;
}

std::string Run::stop_message(StopRule rule, const SampleBlock& b, int row) const {
  const RunOptions& o = options_;
  const double t_s = static_cast<double>(b.k0 + row) * o.config.machine.period_s;
  switch (rule) {
    case StopRule::Interrupted:
      return fmt::format("interrupted at t = {:.3f} s (line {}){}", t_s, line_,
                         o.keep_partial ? "" : "; no trace was kept");
    case StopRule::MaxTime:
      return fmt::format("run stopped at --max-time {} s (line {}, feed override {} %)",
                         o.max_time_s, line_, player_.feed_percent());
    case StopRule::Held:
      return fmt::format(
          "feed held at 0 % override at line {} (t = {:.3f} s) and nothing in the override "
          "schedule resumes it",
          line_, t_s);
    case StopRule::None:
      break;
  }
  return {};
}

void Run::finish(RunStatus status) {
  if (queue_) queue_->finish();
  // An unsettled run's trace is kept partial by the caller when asked for, else completed.
  const RunEnd end{rec_, pipeline_.program_end_blu(), status == RunStatus::Finished};
  for (BlockSink* sink : sinks_) sink->finish(end);
  if (recorder_) recorder_->finish();
}

std::string Run::unsettled_reason() const {
  return fmt::format("the axes did not settle within {} s of the program end",
                     options_.config.settle_timeout_s);
}

std::optional<std::string> Run::keep_partial(std::string_view reason) noexcept {
  if (!options_.keep_partial || !trace_ || !trace_->open()) return std::nullopt;
  if (queue_) {
    try {
      queue_->finish();  // every sample pushed so far reaches the trace
    } catch (...) {      // the run's own error is the one reported
    }
  }
  return trace_->keep_partial(reason);
}

}  // namespace gm
