// gmotion run: the whole pipeline on a program, streaming a trace and printing a summary.
#include "cli/commands.hpp"
#include "cli/run_setup.hpp"
#include "common/status.hpp"
#include "override/live_override.hpp"
#include "override/override_schedule.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/sample_queue.hpp"
#include "trace/run_summary.hpp"
#include "trace/trace_writer.hpp"

#include <fmt/format.h>

#include <unistd.h>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <exception>
#include <fstream>
#include <memory>
#include <optional>
#include <thread>

namespace gm::cli {
namespace {

volatile std::sig_atomic_t g_interrupted = 0;
extern "C" void on_sigint(int) {
  g_interrupted = 1;
}

struct RunFlags {
  std::string program;
  MachineFlags machine;
  std::string trace_path;
  std::string trace_format = "csv";
  int decimate = 1;
  std::string summary_json;
  double override_pct = 100.0;
  double rapid_override_pct = 100.0;
  std::string override_file;
  std::string record_override;
  bool realtime = false;
  double max_time_s = 0.0;
  bool keep_partial = false;
};

// A run's trace, held by run()'s caller so that --keep-partial can keep it when the run fails.
struct RunTrace {
  std::unique_ptr<TraceWriter> writer;
  std::string unsettled;  ///< why run() returned 1 without an error (the axes did not settle)
};

// --keep-partial: when the run fails, hands every sample pushed so far to the consumer before the
// queue is destroyed (which drops them), so the kept trace has all of them.
class DrainOnFailure {
 public:
  explicit DrainOnFailure(std::optional<SampleQueue>* queue) : queue_(queue) {}
  ~DrainOnFailure() {
    if (queue_ == nullptr || !*queue_ || std::uncaught_exceptions() == exceptions_) return;
    try {
      (*queue_)->finish();
    } catch (...) {  // the run's own error is the one reported
    }
  }
  DrainOnFailure(const DrainOnFailure&) = delete;
  DrainOnFailure& operator=(const DrainOnFailure&) = delete;

 private:
  std::optional<SampleQueue>* queue_;
  int exceptions_ = std::uncaught_exceptions();
};

// Writes the overrides in effect as a schedule that --override-file replays sample-exactly:
// one `t_s,percent` (or `t_s,rapid=percent`) line per change, t = k·T printed round-trip exact.
class OverrideRecorder {
 public:
  OverrideRecorder(const std::string& path, double period_s) : out_(path), period_s_(period_s) {
    if (!out_) throw InputError(fmt::format("cannot write override record '{}'", path));
    out_ << "# gmotion override record: replay with --override-file (t_s,percent; "
            "t_s,rapid=percent)\n";
  }
  void sample(std::int64_t k, double feed_pct, double rapid_pct) {
    const double t = static_cast<double>(k) * period_s_;
    if (feed_pct != feed_) out_ << fmt::format("{:.17g},{:.17g}\n", t, feed_pct), feed_ = feed_pct;
    if (rapid_pct != rapid_)
      out_ << fmt::format("{:.17g},rapid={:.17g}\n", t, rapid_pct), rapid_ = rapid_pct;
  }
  void finish() {
    out_.flush();
    if (!out_) throw InputError("cannot write the override record");
  }

 private:
  std::ofstream out_;
  double period_s_;
  double feed_ = -1.0, rapid_ = -1.0;
};

int run(const RunFlags& f, RunTrace& out) {
  // Caught from the start, so an interrupt during the check of a long program is not lost
  // (a background job's SIGINT is otherwise ignored); the run stops at its first sample.
  std::signal(SIGINT, on_sigint);
  std::signal(SIGTERM, on_sigint);
  RunConfig cfg;
  cfg.machine = resolve_machine(f.machine);
  cfg.servo = !f.machine.no_servo;
  const double max_pct = cfg.machine.max_override * 100.0;
  for (auto [flag, v] : {std::pair{"--override", f.override_pct},
                         std::pair{"--rapid-override", f.rapid_override_pct}})
    if (!(v >= 0.0) || v > max_pct + 1e-9)
      throw InputError(fmt::format("{} {} is outside 0..{} % (the machine's maximum override)",
                                   flag, v, max_pct));
  const OverrideSchedule schedule = f.override_file.empty()
                                        ? OverrideSchedule{}
                                        : OverrideSchedule::load(f.override_file, max_pct);

  ProgramInput program(f.program);
  InterpreterOptions opts;
  opts.machine = &cfg.machine;
  opts.block_delete = f.machine.block_delete;
  if (!validate_program(program, opts)) return static_cast<int>(ExitCode::InputError);

  // The summary, the trace and the contour error consume the samples; with two cores they do
  // it on the second one, fed in batches (same records, same order: the outputs are
  // byte-identical). Real-time runs stay on one thread.
  const bool two_threads = !f.realtime && std::thread::hardware_concurrency() >= 2;
  cfg.defer_contour = two_threads;
  ProgramStream stream(program.rewind(), program.name(), opts);
  Pipeline pipeline(cfg, stream);

  std::unique_ptr<TraceWriter>& trace = out.writer;
  if (!f.trace_path.empty()) {
    TraceMeta meta;
    meta.program = program.name();
    meta.machine_name = cfg.machine.name;
    meta.machine_source = cfg.machine.source;
    meta.profile = cfg.machine.profile;
    meta.taps = static_cast<int>(pipeline.taps().integer.size());
    meta.tau_s = cfg.machine.tau_s;
    meta.period_s = cfg.machine.period_s;
    meta.blu_mm = cfg.machine.blu_mm();
    meta.servo = cfg.servo;
    meta.decimate = f.decimate;
    meta.status_line = f.keep_partial;
    trace = std::make_unique<TraceWriter>(
        f.trace_path, f.trace_format == "bin" ? TraceFormat::Binary : TraceFormat::Csv, meta);
  }

  RunSummary summary(cfg.machine);
  OverridePlayer player(schedule, cfg.machine.period_s, f.override_pct, f.rapid_override_pct);
  std::optional<LiveOverride> live;
  if (f.realtime) live.emplace(STDIN_FILENO, max_pct);
  std::optional<OverrideRecorder> recorder;
  if (!f.record_override.empty()) recorder.emplace(f.record_override, cfg.machine.period_s);
  std::optional<ContourMeter> meter;
  if (cfg.defer_contour) meter.emplace(pipeline.contour_meter());
  auto consume = [&](SampleRecord& r, const Motion* started) {
    if (meter) meter->measure(r, started);
    summary.add(r);
    if (trace) trace->write(r);
  };
  std::optional<SampleQueue> queue;
  if (two_threads) queue.emplace(consume);
  const DrainOnFailure drain(f.keep_partial ? &queue : nullptr);
  OverrideInput ovr;
  SampleRecord rec;  // after the loop: the last sample (a step that is not Working leaves it)
  const bool progress = isatty(STDERR_FILENO) != 0 && !f.realtime;
  const auto t0 = std::chrono::steady_clock::now();
  auto next_progress = t0 + std::chrono::seconds(1);
  std::int64_t k = 0;
  int line = 0;
  bool live_open = f.realtime;
  PipelineStatus st;
  for (;; ++k) {
    player.advance(k, line);
    if (live_open) {
      double feed = player.feed_percent(), rapid = player.rapid_percent();
      live_open = live->poll(feed, rapid);
      player.set(feed, rapid);
    }
    ovr.feed_scale = player.feed_scale();
    ovr.rapid_scale = player.rapid_scale();
    if (recorder) recorder->sample(k, player.feed_percent(), player.rapid_percent());
    if ((st = pipeline.step(ovr, rec)) != PipelineStatus::Working) break;
    line = rec.line;
    if (g_interrupted != 0)
      throw InputError(fmt::format("interrupted at t = {:.3f} s (line {}){}", rec.t_s, rec.line,
                                   f.keep_partial ? "" : "; no trace was kept"));
    if (f.max_time_s > 0 && rec.t_s > f.max_time_s) {
      throw InputError(fmt::format("run stopped at --max-time {} s (line {}, feed override {} %)",
                                   f.max_time_s, rec.line, player.feed_percent()));
    }
    if ((rec.events & kEventHold) != 0 && !live_open && !player.may_change())
      throw InputError(
          fmt::format("feed held at 0 % override at line {} (t = {:.3f} s) and nothing in the "
                      "override schedule resumes it",
                      rec.line, rec.t_s));
    if (f.realtime)
      std::this_thread::sleep_until(
          t0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                   std::chrono::duration<double>(rec.t_s + cfg.machine.period_s)));
    if (queue)
      queue->push(rec, pipeline.started_motion());
    else
      consume(rec, nullptr);  // step() measured the contour itself
    if (progress && (rec.k & 0xFFFF) == 0 && std::chrono::steady_clock::now() > next_progress) {
      fmt::print(stderr, "\r{}: t = {:.1f} s, line {}   ", program.name(), rec.t_s, rec.line);
      next_progress += std::chrono::seconds(1);
    }
  }
  if (queue) queue->finish();
  if (progress && std::chrono::steady_clock::now() > t0 + std::chrono::seconds(1))
    fmt::print(stderr, "\n");
  summary.finish(rec, pipeline.program_end_blu(), st == PipelineStatus::Finished);
  const bool complete = st == PipelineStatus::Finished;
  if (trace && (complete || !f.keep_partial)) trace->finish();  // else kept partial by the caller
  if (!complete)
    out.unsettled =
        fmt::format("the axes did not settle within {} s of the program end", cfg.settle_timeout_s);
  if (recorder) recorder->finish();

  std::FILE* text_out = f.trace_path == "-" ? stderr : stdout;
  fmt::print(text_out, "{}: {} on {} ({}, tau {} s, T {} s, {} taps, servo {})\n", program.name(),
             "gmotion run", cfg.machine.name, cfg.machine.profile, cfg.machine.tau_s,
             cfg.machine.period_s, pipeline.taps().integer.size(), cfg.servo ? "on" : "off");
  fmt::print(text_out, "tool table {} ({} tools)\n", cfg.machine.tool_table.source,
             cfg.machine.tool_table.tools.size());
  fmt::print(text_out, "{}", summary.text());
  if (!f.summary_json.empty()) {
    std::ofstream js(f.summary_json);
    js << summary.json();
    if (!js) throw InputError(fmt::format("cannot write summary '{}'", f.summary_json));
  }
  return complete ? 0 : static_cast<int>(ExitCode::InputError);
}

// run(); with --keep-partial a run that fails keeps the trace written so far as FILE.partial, its
// status line saying why, and leaves main a note of where it is.
int run_keeping_partial(const RunFlags& f, Context& ctx) {
  RunTrace trace;
  auto keep = [&](const std::string& reason) {
    if (!f.keep_partial || !trace.writer || !trace.writer->open()) return;
    const std::string kept = trace.writer->keep_partial(reason);
    ctx.note = kept.empty() ? "no partial trace could be kept (its header was never written)"
                            : fmt::format("partial trace kept at {}", kept);
  };
  try {
    const int rc = run(f, trace);
    if (rc != 0) keep(trace.unsettled);
    return rc;
  } catch (const std::exception& e) {
    keep(e.what());
    throw;
  }
}

}  // namespace

void add_run(CLI::App& app, Context& ctx) {
  auto flags = std::make_shared<RunFlags>();
  auto* sub = app.add_subcommand("run", "Run the whole pipeline on a program: trace and summary");
  sub->add_option("program", flags->program, "G-code program (.nc, .ngc), or - for stdin")
      ->required();
  add_machine_flags(sub, flags->machine);
  auto* trace = sub->add_option("--trace", flags->trace_path,
                                "Write the per-sample encoder trace here (- = stdout)");
  sub->add_option("--trace-format", flags->trace_format, "csv or bin")
      ->check(CLI::IsMember({"csv", "bin"}));
  sub->add_option("--decimate", flags->decimate, "Write every K-th sample")
      ->check(CLI::PositiveNumber);
  sub->add_option("--summary-json", flags->summary_json, "Write the summary as JSON to this file");
  sub->add_option("--override", flags->override_pct,
                  "Feed override at the start, percent (default 100)");
  sub->add_option("--rapid-override", flags->rapid_override_pct,
                  "Rapid override at the start, percent (default 100)");
  sub->add_option(
      "--override-file", flags->override_file,
      "Override schedule: lines t_s,percent | line:N,percent | t_s,rapid=percent; # comments");
  sub->add_flag(
      "--realtime", flags->realtime,
      "Pace the run at wall-clock speed and read override changes from stdin, one a line: "
      "75 | rapid 25 | + | - | hold");
  sub->add_option(
      "--record-override", flags->record_override,
      "Write the overrides in effect as a schedule that --override-file replays exactly");
  sub->add_option("--max-time", flags->max_time_s,
                  "Stop the run (exit 1) when simulated time passes this, s");
  sub->add_flag(
         "--keep-partial", flags->keep_partial,
         "When the run fails, keep the trace written so far as FILE.partial; a '# status:' header "
         "line says whether the trace is complete or why it is partial")
      ->needs(trace);
  sub->callback([flags, &ctx] {
    if (flags->keep_partial && TraceWriter::written_in_place(flags->trace_path))
      throw CLI::ValidationError(
          "--keep-partial", fmt::format("--trace {} is written in place (stdout, a device or a "
                                        "FIFO), so no partial trace can be kept apart from it; "
                                        "write the trace to a file",
                                        flags->trace_path));
    ctx.exit_code = run_keeping_partial(*flags, ctx);
  });
}

}  // namespace gm::cli
