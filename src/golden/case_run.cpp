// One case: flags parsed as `gmotion run` parses them, then Run stepped to the end on this thread.
#include "golden/case_run.hpp"

#include "common/status.hpp"
#include "machine/machine_file.hpp"
#include "pipeline/run.hpp"
#include "setup/program_input.hpp"
#include "setup/run_settings.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <exception>
#include <sstream>

namespace gm::golden {
namespace {

namespace fs = std::filesystem;

std::string under_root(const Suite& s, const std::string& p) {
  if (p.empty() || fs::path(p).is_absolute()) return p;
  return (s.root / p).lexically_normal().string();
}

// A case's run settings: its flags parsed from the same table as `gmotion run`'s, then its keys;
// paths relative to the suite's root.
setup::RunSettings case_settings(const Suite& s, const GoldenCase& c) {
  setup::RunSettings f;
  f.decimate = c.decimate;
  try {
    setup::parse_flags(f, c.flags);
  } catch (const InputError& e) {
    throw InputError(
        fmt::format("flags '{}': {} (a case takes: {})", c.flags, e.what(), setup::flag_names()));
  }
  auto both = [&](const std::string& key, const std::string& flag_value, const char* flag) {
    if (!key.empty() && !flag_value.empty())
      throw InputError(fmt::format("both the key and the flag {} are given", flag));
  };
  both(c.machine, f.machine_file, "--machine");
  both(c.override_file, f.override_file, "--override-file");
  if (!c.machine.empty()) f.machine_file = c.machine;
  if (!c.override_file.empty()) f.override_file = c.override_file;
  for (std::string* path :
       {&f.machine_file, &f.tool_table, &f.override_file, &f.parameter_file, &f.user_mcode_dir})
    *path = under_root(s, *path);
  std::string dirs;
  for (std::size_t at = 0; at <= f.subroutine_path.size() && !f.subroutine_path.empty();) {
    const std::size_t colon = std::min(f.subroutine_path.find(':', at), f.subroutine_path.size());
    dirs += (dirs.empty() ? "" : ":") + under_root(s, f.subroutine_path.substr(at, colon - at));
    at = colon + 1;
  }
  f.subroutine_path = dirs;
  return f;
}

// The set-up: everything that shapes the motion except the program and the schedule. The
// language flags are listed only when given, so a case without them keeps its hash.
std::string setup_text(const setup::RunSettings& f, const RunOptions& o) {
  std::string text = machine_to_toml(o.config.machine);
  text += fmt::format(
      "\n[run]\nservo = {}\nblock_delete = {}\noverride_percent = {}\nrapid_override_percent = "
      "{}\ndecimate = {}\ncheck_tolerance = {}\nmax_time_s = {}\n",
      o.config.servo, f.block_delete, f.override_pct, f.rapid_override_pct, f.decimate,
      f.check_tolerance, f.max_time_s);
  const setup::RunSettings none;
  std::string language;
  if (f.subroutine_path != none.subroutine_path)
    language += fmt::format("subroutine_path = \"{}\"\n", f.subroutine_path);
  if (f.max_iterations != none.max_iterations)
    language += fmt::format("max_iterations = {}\n", f.max_iterations);
  if (f.dialect != none.dialect) language += fmt::format("dialect = \"{}\"\n", f.dialect);
  if (f.parameter_file != none.parameter_file)
    language += fmt::format("parameter_file = \"{}\"\n", f.parameter_file);
  if (f.no_parameter_file) language += "no_parameter_file = true\n";
  if (!language.empty()) text += "\n[language]\n" + language;
  return text;
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
    const setup::RunSettings f = case_settings(s, c);
    RunOptions o = setup::run_options(f, setup::resolve_machine(f));
    out.setup = setup_text(f, o);
    out.setup_hash = fnv1a64(out.setup);

    setup::ProgramInput program(c.program_path.string());
    // The parameter file is read as `run` reads it, never written: a case must not change the
    // next one's start.
    const InterpreterOptions opts = setup::interpreter_options(f, o.config.machine);
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
    o.trace_path = trace_path;
    o.trace_format = TraceFormat::Binary;
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
