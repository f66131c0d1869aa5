// A run: the pipeline with its overrides, outputs (trace, summary, override record, progress)
// and stop rules, advanced a block of samples per advance() or one per step() (ruckig's update()).
#pragma once

#include "interp/program.hpp"
#include "measure/contour_meter.hpp"
#include "measure/run_summary.hpp"
#include "measure/tolerance_check.hpp"
#include "motion/block_sink.hpp"
#include "motion/canon.hpp"
#include "override/override_schedule.hpp"
#include "pipeline/canon_read_ahead.hpp"
#include "pipeline/pipeline.hpp"
#include "planner/tolerance_planner.hpp"
#include "trace/trace_writer.hpp"

#include <chrono>
#include <csignal>
#include <functional>
#include <istream>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gm {

class LiveOverride;
class OverrideRecorder;
class SampleQueue;

/// Everything a run is asked to do besides the program.
struct RunOptions {
  RunConfig config;          ///< machine (flags applied), servo, settle timeout
  std::string program_name;  ///< for the trace header and messages

  // Overrides.
  double feed_override_pct = 100.0;   ///< at the start
  double rapid_override_pct = 100.0;  ///< at the start
  OverrideSchedule schedule;          ///< changes by time or source line
  int live_fd = -1;  ///< >= 0: real time: pace at wall-clock speed, read changes from this fd

  // Outputs.
  std::string trace_path;  ///< "" = no trace; "-" = stdout
  TraceFormat trace_format = TraceFormat::Csv;
  int decimate = 1;
  bool keep_partial = false;  ///< the trace has a status line; keep_partial() keeps a failed one
  std::string record_override_path;  ///< "" = none
  /// Called about once a second of wall time with the last sample (never in real time).
  std::function<void(const SampleRecord&)> progress;

  // Stop rules (each throws gm::InputError from step()).
  double max_time_s = 0.0;                                  ///< simulated time; 0 = no limit
  const volatile std::sig_atomic_t* interrupted = nullptr;  ///< stop when it becomes non-zero

  /// Measure the contour, summarise and trace on a second thread when the machine has two
  /// cores (never in real time). The outputs are byte-identical either way.
  bool consumer_thread = true;
};

enum class RunStatus {
  Working,   ///< a sample was produced: last() holds it
  Finished,  ///< the program ended and the axes settled; the outputs are complete
  Unsettled  ///< the program ended but the axes did not settle (unsettled_reason()); outputs done
};

/// Owns the pipeline, the override player, the outputs and the stop rules:
///
///     Run run(options, program, interpreter_options);
///     while (run.advance() == RunStatus::Working) {}
///     print(run.summary());
///
/// advance() produces up to a block of samples (kBlockSamples; one in real time), step() one;
/// both give the same samples and outputs. Nothing is allocated per sample. A failed step (stop
/// rule, servo divergence, a write error) throws gm::InputError; with options.keep_partial call
/// keep_partial(reason) then.
///
/// The outputs are BlockSinks: the contour is measured into each block, then the summary, the
/// tolerance check, the trace and any sink added with add_sink() consume it, in that order, on
/// the consumer thread.
class Run {
 public:
  /// Pulls the canonical moves from `source`. Throws gm::InputError on a bad set-up (machine,
  /// override values, trace path, override record path).
  Run(RunOptions options, CanonSource& source);
  /// Interprets `program` itself (opts.machine is set to the run's machine).
  Run(RunOptions options, std::istream& program, InterpreterOptions opts);
  ~Run();
  Run(const Run&) = delete;
  Run& operator=(const Run&) = delete;

  /// Hands every sample to `sink` too (after the run's own outputs), and ends it with the run.
  /// Call before the first step() or advance(); `sink` must outlive the run's last call. It runs
  /// on the consumer thread: read it after the run has ended.
  void add_sink(BlockSink& sink) { sinks_.push_back(&sink); }
  /// The header a trace of this run has (trace_header()), with decimate and no status line.
  TraceMeta trace_meta() const;

  /// Advances one interpolation period T.
  RunStatus step() { return (this->*fill_)(1); }
  /// Advances up to a block of periods (one in real time): Working while the program runs, then
  /// Finished or Unsettled once (the samples of that call are in the outputs).
  RunStatus advance() { return (this->*fill_)(realtime_ ? 1 : kBlockSamples); }

  /// The last sample produced. With the consumer thread its contour fields are filled on the
  /// consumer's copy, not here (set consumer_thread = false to read them per step).
  const SampleRecord& last() const { return rec_; }
  /// Complete once step() has returned Finished or Unsettled.
  const RunSummary& summary() const { return summary_; }
  /// The contour error against the tolerance in force (G64 P), complete with summary().
  const ToleranceCheck& tolerance() const { return tolerance_; }
  const Pipeline& pipeline() const { return pipeline_; }
  const RunConfig& config() const { return options_.config; }
  const RunOptions& options() const { return options_; }
  /// Why the run ended Unsettled.
  std::string unsettled_reason() const;
  /// True when options.progress was called at least once.
  bool progress_shown() const { return progress_shown_; }

  /// After a failure, with options.keep_partial: hands the samples produced so far to the
  /// outputs, then keeps the trace as FILE.partial with its status line saying `reason`.
  /// Returns that path; "" when not even the header could be kept; nullopt when there is no
  /// trace to keep (none asked for, no keep_partial, or already complete). Never throws.
  std::optional<std::string> keep_partial(std::string_view reason) noexcept;

 private:
  /// Both public constructors: the moves from `source`, or else interpreted from `program`.
  Run(RunOptions options, CanonSource* source, std::istream* program, InterpreterOptions opts);
  void init();
  /// The stop rules a run checks on every row, in the order they are checked.
  enum class StopRule { None, Interrupted, MaxTime, Held };
  /// The first stop rule row `row` of `b` breaks (None: none does); cheap, checked per row.
  StopRule broken_rule(const SampleBlock& b, int row) const;
  /// The message of `rule`, broken at row `row` of `b`.
  std::string stop_message(StopRule rule, const SampleBlock& b, int row) const;
  /// Produces up to `max_rows` samples (at most to the end of the current block) for a machine
  /// of N axes: the pipeline's command_n<N> row by row, then its stages_n<N> over them.
  template <int N>
  RunStatus fill_n(int max_rows);
  /// stages_n over rows first.. of `b`; on a servo divergence the rows before it reach the
  /// outputs before the error is rethrown.
  template <int N>
  void stage_rows(SampleBlock& b, int first);
  /// Measures the contour of rows first.. of `b` and hands them to the sinks (on the consumer
  /// thread, or on this one when there is none).
  template <int N>
  void consume_rows(SampleBlock& b, int first);
  void finish(RunStatus status);

  RunOptions options_;
  std::unique_ptr<ProgramStream> stream_;  ///< when the run interprets the program itself
  /// G64 P: caps speeds and pauses at corners for blocks with a tolerance; hands every other
  /// block on unchanged.
  std::unique_ptr<TolerancePlanner> planner_;
  /// With the consumer thread: the planner read ahead on a thread of its own (null: the
  /// pipeline reads it itself).
  std::unique_ptr<CanonReadAhead> ahead_;
  Pipeline pipeline_;
  RunSummary summary_;
  ToleranceCheck tolerance_;
  OverridePlayer player_;
  std::unique_ptr<LiveOverride> live_;
  std::unique_ptr<OverrideRecorder> recorder_;
  std::unique_ptr<TraceWriter> trace_;
  std::optional<ContourMeter> meter_;   ///< measures the contour of every row (consume_rows)
  std::vector<BlockSink*> sinks_;       ///< the outputs, in order: summary, tolerance, trace, added
  std::unique_ptr<SampleQueue> queue_;  ///< last: its thread uses the members above
  std::unique_ptr<SampleBlock> block_;  ///< the block filled without the consumer thread
  OverrideInput ovr_;
  SampleRecord rec_;  ///< the last sample produced
  std::int64_t k_ = 0;
  int line_ = 0;
  bool live_open_ = false;
  bool progress_shown_ = false;
  bool realtime_ = false;
  std::chrono::steady_clock::time_point t0_, next_progress_;
  /// fill_n for the machine's axis count, chosen once in init().
  RunStatus (Run::*fill_)(int) = nullptr;
  /// Hands a block to the outputs on the consumer thread (consume_rows for the axis count).
  void (Run::*consume_block_)(SampleBlock&, int) = nullptr;
};

}  // namespace gm
