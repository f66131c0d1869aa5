// The flags of `gmotion run`, and running a program with them: shared by `run` and `report`.
#pragma once

#include "cli/commands.hpp"
#include "pipeline/run.hpp"
#include "setup/program_input.hpp"
#include "setup/run_settings.hpp"

#include <CLI/CLI.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace gm::cli {

using setup::ProgramInput;

/// `gmotion run`'s arguments: the program, the run settings, and the flags that only choose the
/// output files (which stay here).
struct RunFlags {
  std::string program;
  setup::RunSettings settings;  ///< every flag that changes the run (src/setup's table)
  std::string trace_path;
  std::string trace_format = "csv";
  std::string summary_json;
  std::string record_override;
  bool realtime = false;
  bool keep_partial = false;
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
