// gmotion run: the whole pipeline on a program, streaming a trace and printing a summary.
#include "cli/commands.hpp"
#include "cli/run_setup.hpp"
#include "common/status.hpp"
#include "pipeline/pipeline.hpp"
#include "trace/run_summary.hpp"
#include "trace/trace_writer.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <unistd.h>

namespace gm::cli {
namespace {

struct RunFlags {
  std::string program;
  MachineFlags machine;
  std::string trace_path;
  std::string trace_format = "csv";
  int decimate = 1;
  std::string summary_json;
  double override_pct = 100.0;
};

int run(const RunFlags& f) {
  RunConfig cfg;
  cfg.machine = resolve_machine(f.machine);
  cfg.servo = !f.machine.no_servo;
  if (!(f.override_pct >= 0.0) || f.override_pct > cfg.machine.max_override * 100.0 + 1e-9)
    throw InputError(fmt::format("--override {} is outside 0..{} % (the machine's maximum override)",
                                 f.override_pct, cfg.machine.max_override * 100.0));

  ProgramInput program(f.program);
  InterpreterOptions opts;
  opts.machine = &cfg.machine;
  opts.block_delete = f.machine.block_delete;
  if (!validate_program(program, opts)) return static_cast<int>(ExitCode::InputError);

  ProgramStream stream(program.rewind(), program.name(), opts);
  Pipeline pipeline(cfg, stream);

  std::unique_ptr<TraceWriter> trace;
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
    trace = std::make_unique<TraceWriter>(f.trace_path, f.trace_format == "bin" ? TraceFormat::Binary : TraceFormat::Csv, meta);
  }

  RunSummary summary(cfg.machine);
  OverrideInput ovr;
  ovr.feed_scale = f.override_pct / 100.0;
  SampleRecord rec, last;
  const bool progress = isatty(STDERR_FILENO) != 0;
  const auto t0 = std::chrono::steady_clock::now();
  auto next_progress = t0 + std::chrono::seconds(1);
  PipelineStatus st;
  while ((st = pipeline.step(ovr, rec)) == PipelineStatus::Working) {
    summary.add(rec);
    if (trace) trace->write(rec);
    last = rec;
    if (progress && (rec.k & 0xFFFF) == 0 && std::chrono::steady_clock::now() > next_progress) {
      fmt::print(stderr, "\r{}: t = {:.1f} s, line {}   ", program.name(), rec.t_s, rec.line);
      next_progress += std::chrono::seconds(1);
    }
  }
  if (progress && std::chrono::steady_clock::now() > t0 + std::chrono::seconds(1)) fmt::print(stderr, "\n");
  summary.finish(last, pipeline.program_end_blu(), st == PipelineStatus::Finished);
  if (trace) trace->finish();

  std::FILE* text_out = f.trace_path == "-" ? stderr : stdout;
  fmt::print(text_out, "{}: {} on {} ({}, tau {} s, T {} s, {} taps, servo {})\n", program.name(),
             "gmotion run", cfg.machine.name, cfg.machine.profile, cfg.machine.tau_s, cfg.machine.period_s,
             pipeline.taps().integer.size(), cfg.servo ? "on" : "off");
  fmt::print(text_out, "{}", summary.text());
  if (!f.summary_json.empty()) {
    std::ofstream js(f.summary_json);
    js << summary.json();
    if (!js) throw InputError(fmt::format("cannot write summary '{}'", f.summary_json));
  }
  return st == PipelineStatus::Finished ? 0 : static_cast<int>(ExitCode::InputError);
}

}  // namespace

void add_run(CLI::App& app, Context& ctx) {
  auto flags = std::make_shared<RunFlags>();
  auto* sub = app.add_subcommand("run", "Run the whole pipeline on a program: trace and summary");
  sub->add_option("program", flags->program, "G-code program (.nc, .ngc), or - for stdin")->required();
  add_machine_flags(sub, flags->machine);
  sub->add_option("--trace", flags->trace_path, "Write the per-sample encoder trace here (- = stdout)");
  sub->add_option("--trace-format", flags->trace_format, "csv or bin")->check(CLI::IsMember({"csv", "bin"}));
  sub->add_option("--decimate", flags->decimate, "Write every K-th sample")->check(CLI::PositiveNumber);
  sub->add_option("--summary-json", flags->summary_json, "Write the summary as JSON to this file");
  sub->add_option("--override", flags->override_pct, "Constant feed override, percent (default 100)");
  sub->callback([flags, &ctx] { ctx.exit_code = run(*flags); });
}

}  // namespace gm::cli
