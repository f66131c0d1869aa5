// The flags of `gmotion run`, and running a program with them: shared by `run` and `report`.
#pragma once

#include "cli/commands.hpp"
#include "cli/language_flags.hpp"
#include "cli/run_setup.hpp"
#include "pipeline/run.hpp"

#include <CLI/CLI.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace gm::cli {

struct RunFlags {
  std::string program;
  MachineFlags machine;
  LanguageFlags language;
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
  std::optional<double> tolerance_mm;  ///< --tolerance: the machine's path_tolerance_mm
  bool check_tolerance = false;        ///< --check-tolerance: exit 1 if a sample exceeds it
  std::string tolerance_on;            ///< --tolerance-on acc_dec|encoder (machine tolerance_on)
};

/// What a caller of run_with_flags() sees besides the printed output (`report` uses both).
struct RunHooks {
  /// Called once the run is set up, before its first sample: the place to add_sink().
  std::function<void(Run&)> started;
  /// Called once the run has ended (finished or unsettled), before the summary is printed,
  /// with the program (rewind() it to read it again).
  std::function<void(ProgramInput&, const Run&)> finished;
};

/// Adds the program argument and every flag of `gmotion run` to `sub`. Call
/// validate_run_flags() in the callback.
void add_run_flags(CLI::App* sub, RunFlags& flags);
/// The checks `run` makes before running (--keep-partial needs a trace written to a file).
/// Throws CLI::ValidationError.
void validate_run_flags(const RunFlags& flags);

/// Runs the program as `gmotion run` does (same output, same exit code), calling `hooks`;
/// with --keep-partial a failed run keeps its trace and leaves ctx.note saying where.
int run_with_flags(const RunFlags& flags, Context& ctx, const RunHooks& hooks = {});

}  // namespace gm::cli
