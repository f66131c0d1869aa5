// The flags of `gmotion run`, and running a program with them: shared by `run` and `report`.
#include "cli/run_flags.hpp"

#include "cli/settings_flags.hpp"
#include "common/status.hpp"
#include "override/override_schedule.hpp"
#include "trace/trace_writer.hpp"

#include <fmt/format.h>

#include <unistd.h>
#include <csignal>
#include <cstdio>
#include <exception>
#include <fstream>

namespace gm::cli {
namespace {

volatile std::sig_atomic_t g_interrupted = 0;
extern "C" void on_sigint(int) {
  g_interrupted = 1;
}

int run(const RunFlags& f, std::unique_ptr<Run>& run_out, const RunHooks& hooks) {
  // Caught from the start, so an interrupt during the check of a long program is not lost
  // (a background job's SIGINT is otherwise ignored); the run stops at its first sample.
  std::signal(SIGINT, on_sigint);
  std::signal(SIGTERM, on_sigint);
  const setup::RunSettings& set = f.settings;
  RunOptions o = setup::run_options(set, setup::resolve_machine(set));

  ProgramInput program(f.program);
  InterpreterOptions opts = setup::interpreter_options(set, o.config.machine);
  if (!setup::validate_program(program, opts)) return static_cast<int>(ExitCode::InputError);
  opts.save_parameters = true;  // the parameter file is written once, after the real pass

  o.program_name = program.name();
  if (f.realtime) o.live_fd = STDIN_FILENO;
  o.trace_path = f.trace_path;
  o.trace_format = f.trace_format == "bin" ? TraceFormat::Binary : TraceFormat::Csv;
  o.keep_partial = f.keep_partial;
  o.record_override_path = f.record_override;
  if (isatty(STDERR_FILENO) != 0)
    o.progress = [name = program.name()](const SampleRecord& r) {
      fmt::print(stderr, "\r{}: t = {:.1f} s, line {}   ", name, r.t_s, r.line);
    };
  o.interrupted = &g_interrupted;
  run_out = std::make_unique<Run>(std::move(o), program.rewind(), opts);
  Run& run = *run_out;
  if (hooks.started) hooks.started(run);

  RunStatus st;
  while ((st = run.advance()) == RunStatus::Working) {
  }
  if (run.progress_shown()) fmt::print(stderr, "\n");
  if (hooks.finished) hooks.finished(program, run);

  const RunConfig& cfg = run.config();
  std::FILE* text_out = f.trace_path == "-" ? stderr : stdout;
  std::string own;  // axes with their own Acc/Dec ([axes.<l>.accdec])
  for (int a = 0; a < cfg.machine.axis_count(); ++a) {
    const AxisConfig& c = cfg.machine.axes[static_cast<std::size_t>(a)];
    if (!c.accdec_profile.empty() || c.accdec_tau_s > 0.0)
      own += fmt::format("; {}: {}, tau {} s", cfg.machine.layout.letter(a),
                         c.accdec_profile.empty() ? cfg.machine.profile : c.accdec_profile,
                         c.accdec_tau_s > 0.0 ? c.accdec_tau_s : cfg.machine.tau_s);
  }
  fmt::print(text_out, "{}: {} on {} ({}, tau {} s, T {} s, {} taps, servo {}{})\n", program.name(),
             "gmotion run", cfg.machine.name, cfg.machine.profile, cfg.machine.tau_s,
             cfg.machine.period_s, run.pipeline().taps().integer.size(), cfg.servo ? "on" : "off",
             own);
  fmt::print(text_out, "tool table {} ({} tools)\n", cfg.machine.tool_table.source,
             cfg.machine.tool_table.tools.size());
  fmt::print(text_out, "{}", run.summary().text());
  fmt::print(text_out, "{}", run.tolerance().text());
  if (!f.summary_json.empty()) {
    std::ofstream js(f.summary_json);
    js << run.summary().json(run.tolerance().json_member());
    if (!js) throw InputError(fmt::format("cannot write summary '{}'", f.summary_json));
  }
  if (set.check_tolerance && run.tolerance().exceeded()) {
    fmt::print(stderr, "gmotion run: --check-tolerance: {} samples exceed the tolerance in force\n",
               run.tolerance().cutting().over + run.tolerance().rapids().over);
    return static_cast<int>(ExitCode::InputError);
  }
  return st == RunStatus::Finished ? 0 : static_cast<int>(ExitCode::InputError);
}

}  // namespace

void add_run_flags(CLI::App* sub, RunFlags& flags) {
  sub->add_option("program", flags.program, "G-code program (.nc, .ngc), or - for stdin")
      ->required();
  add_setting_flags(sub, flags.settings, setup::kAllSettings);
  auto* trace = sub->add_option("--trace", flags.trace_path,
                                "Write the per-sample encoder trace here (- = stdout)");
  sub->add_option("--trace-format", flags.trace_format, "csv or bin")
      ->check(CLI::IsMember({"csv", "bin"}));
  sub->add_option("--summary-json", flags.summary_json, "Write the summary as JSON to this file");
  sub->add_flag(
      "--realtime", flags.realtime,
      "Pace the run at wall-clock speed and read override changes from stdin, one a line: "
      "75 | rapid 25 | + | - | hold");
  sub->add_option(
      "--record-override", flags.record_override,
      "Write the overrides in effect as a schedule that --override-file replays exactly");
  sub->add_flag(
         "--keep-partial", flags.keep_partial,
         "When the run fails, keep the trace written so far as FILE.partial; a '# status:' header "
         "line says whether the trace is complete or why it is partial")
      ->needs(trace);
}

void validate_run_flags(const RunFlags& flags) {
  if (flags.keep_partial && TraceWriter::written_in_place(flags.trace_path))
    throw CLI::ValidationError("--keep-partial",
                               fmt::format("--trace {} is written in place (stdout, a device or a "
                                           "FIFO), so no partial trace can be kept apart from it; "
                                           "write the trace to a file",
                                           flags.trace_path));
}

// run(); with --keep-partial a run that fails keeps the trace written so far as FILE.partial, its
// status line saying why, and leaves main a note of where it is.
int run_with_flags(const RunFlags& f, Context& ctx, const RunHooks& hooks) {
  std::unique_ptr<Run> run_state;
  auto keep = [&](const std::string& reason) {
    if (!f.keep_partial || !run_state) return;
    const std::optional<std::string> kept = run_state->keep_partial(reason);
    if (!kept) return;
    ctx.note = kept->empty() ? "no partial trace could be kept (its header was never written)"
                             : fmt::format("partial trace kept at {}", *kept);
  };
  try {
    const int rc = run(f, run_state, hooks);
    if (rc != 0) keep(run_state ? run_state->unsettled_reason() : "");
    return rc;
  } catch (const std::exception& e) {
    keep(e.what());
    throw;
  }
}

}  // namespace gm::cli
