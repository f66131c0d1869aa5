// One case: flags parsed as `gmotion run` parses them, then Run stepped to the end on this thread.
#include "golden/case_run.hpp"

#include "cli/run_setup.hpp"
#include "common/status.hpp"
#include "machine/machine_file.hpp"
#include "override/override_schedule.hpp"
#include "pipeline/run.hpp"

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <exception>
#include <optional>
#include <sstream>

namespace gm::golden {
namespace {

namespace fs = std::filesystem;

struct CaseFlags {
  cli::MachineFlags machine;
  std::string override_file;
  double override_pct = 100.0;
  double rapid_override_pct = 100.0;
  int decimate = 1;
  std::optional<double> tolerance_mm;
  bool check_tolerance = false;
  double max_time_s = 0.0;
};

// Parses a case's flags with the same option definitions as `gmotion run`.
CaseFlags parse_flags(const GoldenCase& c) {
  CaseFlags f;
  f.decimate = c.decimate;
  CLI::App app{"golden case"};
  cli::add_machine_flags(&app, f.machine);
  app.add_option("--override", f.override_pct);
  app.add_option("--rapid-override", f.rapid_override_pct);
  app.add_option("--override-file", f.override_file);
  app.add_option("--decimate", f.decimate)->check(CLI::PositiveNumber);
  app.add_option("--tolerance", f.tolerance_mm);
  app.add_flag("--check-tolerance", f.check_tolerance);
  app.add_option("--max-time", f.max_time_s);
  try {
    app.parse(c.flags, false);
  } catch (const CLI::ParseError& e) {
    throw InputError(
        fmt::format("flags '{}': {} (a case takes: {})", c.flags, e.what(), kCaseFlagsHelp));
  }
  auto both = [&](const std::string& key, const std::string& flag_value, const char* flag) {
    if (!key.empty() && !flag_value.empty())
      throw InputError(fmt::format("both the key and the flag {} are given", flag));
  };
  both(c.machine, f.machine.machine_file, "--machine");
  both(c.override_file, f.override_file, "--override-file");
  if (!c.machine.empty()) f.machine.machine_file = c.machine;
  if (!c.override_file.empty()) f.override_file = c.override_file;
  return f;
}

std::string under_root(const Suite& s, const std::string& p) {
  if (p.empty() || fs::path(p).is_absolute()) return p;
  return (s.root / p).lexically_normal().string();
}

}  // namespace

std::uint64_t fnv1a64(std::string_view text) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char ch : text) h = (h ^ ch) * 0x100000001b3ULL;
  return h;
}

CaseOutput run_case(const Suite& s, const GoldenCase& c, const std::string& trace_path) {
  CaseOutput out;
  try {
    CaseFlags f = parse_flags(c);
    f.machine.machine_file = under_root(s, f.machine.machine_file);
    f.machine.tool_table = under_root(s, f.machine.tool_table);
    RunOptions o;
    o.config.machine = cli::resolve_machine(f.machine);
    o.config.servo = !f.machine.no_servo;
    const double max_pct = cli::apply_run_limits(o.config.machine, f.tolerance_mm, f.override_pct,
                                                 f.rapid_override_pct);
    if (!f.override_file.empty())
      o.schedule = OverrideSchedule::load(under_root(s, f.override_file), max_pct);

    // The set-up: everything that shapes the motion except the program and the schedule.
    out.setup = machine_to_toml(o.config.machine);
    out.setup += fmt::format(
        "\n[run]\nservo = {}\nblock_delete = {}\noverride_percent = {}\nrapid_override_percent = "
        "{}\ndecimate = {}\ncheck_tolerance = {}\nmax_time_s = {}\n",
        o.config.servo, f.machine.block_delete, f.override_pct, f.rapid_override_pct, f.decimate,
        f.check_tolerance, f.max_time_s);
    out.setup_hash = fnv1a64(out.setup);

    cli::ProgramInput program(c.program_path.string());
    InterpreterOptions opts;
    opts.machine = &o.config.machine;
    opts.block_delete = f.machine.block_delete;
    std::ostringstream diag;
    const CheckSummary chk =
        check_program(program.rewind(), c.program, opts, diag, CheckThreads::Single);
    if (chk.errors > 0) {
      std::string text = diag.str();
      while (!text.empty() && text.back() == '\n') text.pop_back();
      throw InputError(fmt::format("{} error{} in the program:\n{}", chk.errors,
                                   chk.errors == 1 ? "" : "s", text));
    }
    o.program_name = c.program;
    o.feed_override_pct = f.override_pct;
    o.rapid_override_pct = f.rapid_override_pct;
    o.trace_path = trace_path;
    o.trace_format = TraceFormat::Binary;
    o.decimate = f.decimate;
    o.max_time_s = f.max_time_s;
    o.consumer_thread = false;  // the cases themselves fill the cores
    Run run(std::move(o), program.rewind(), opts);
    RunStatus st;
    while ((st = run.advance()) == RunStatus::Working) {
    }
    if (st != RunStatus::Finished) throw InputError(run.unsettled_reason());
    if (f.check_tolerance && run.tolerance().exceeded())
      throw InputError(fmt::format("--check-tolerance: {} samples exceed the tolerance in force",
                                   run.tolerance().cutting().over + run.tolerance().rapids().over));
    out.summary_json = run.summary().json(run.tolerance().json_member());
    out.complete = true;
  } catch (const std::exception& e) {
    out.error = e.what();
    std::error_code ec;
    fs::remove(trace_path, ec);
  }
  return out;
}

}  // namespace gm::golden
