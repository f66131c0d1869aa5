// The subcommands of the gmotion CLI; each file cmd_<name>.cpp adds one.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace gm::cli {

/// Shared between main and the subcommands: the exit code the chosen subcommand produced.
struct Context {
  int exit_code = 0;
  std::string note;  ///< printed by main on stderr after the subcommand's output and error, if any
};

// Each adds its subcommand to `app`; the callback stores its exit code in `ctx`.
void add_check(CLI::App& app, Context& ctx);    ///< gmotion check PROGRAM
void add_moves(CLI::App& app, Context& ctx);    ///< gmotion moves PROGRAM
void add_design(CLI::App& app, Context& ctx);   ///< gmotion design ... (paper Fig. 9)
void add_analyze(CLI::App& app, Context& ctx);  ///< gmotion analyze radius-error|response
void add_run(CLI::App& app, Context& ctx);      ///< gmotion run PROGRAM (the whole pipeline)
void add_diff(CLI::App& app, Context& ctx);     ///< gmotion diff A B (trace comparison)
void add_compare(CLI::App& app, Context& ctx);  ///< gmotion compare PROGRAM (profiles side by side)
void add_golden(CLI::App& app, Context& ctx);   ///< gmotion golden record|verify SUITE
void add_report(CLI::App& app, Context& ctx);   ///< gmotion report PROGRAM -o PAGE.html

}  // namespace gm::cli
