// gmotion command line: subcommands over the pipeline library; maps errors to exit codes.
#include "cli/commands.hpp"
#include "common/status.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <exception>

namespace {

int run_main(int argc, char** argv) {
  using gm::ExitCode;
  CLI::App app{
      "gmotion — a G-code executing motion interpreter: parser, sample-data interpolator,\n"
      "FIR Acc/Dec (Chen & Lee 1998), servo model and encoder-trace logger.\n"
      "Exit codes: 0 ok, 1 program or input error, 2 usage error, 3 internal error."};
  app.set_version_flag("--version", std::string("gmotion ") + GMOTION_VERSION);
  app.require_subcommand(1);

  gm::cli::Context ctx;
  gm::cli::add_run(app, ctx);
  gm::cli::add_compare(app, ctx);
  gm::cli::add_diff(app, ctx);
  gm::cli::add_check(app, ctx);
  gm::cli::add_moves(app, ctx);
  gm::cli::add_design(app, ctx);
  gm::cli::add_analyze(app, ctx);
  gm::cli::add_golden(app, ctx);
  gm::cli::add_report(app, ctx);

  int code = 0;
  try {
    app.parse(argc, argv);
    code = ctx.exit_code;
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);  // prints help/version (rc 0) or the usage error
    return rc == 0 ? 0 : static_cast<int>(ExitCode::UsageError);
  } catch (const gm::InputError& e) {
    std::fflush(stdout);
    fmt::print(stderr, "gmotion: error: {}\n", e.what());
    code = static_cast<int>(ExitCode::InputError);
  } catch (const std::exception& e) {
    std::fflush(stdout);
    fmt::print(stderr, "gmotion: internal error: {}\n", e.what());
    code = static_cast<int>(ExitCode::InternalError);
  }
  if (!ctx.note.empty()) {
    std::fflush(stdout);
    fmt::print(stderr, "gmotion: {}\n", ctx.note);
  }
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  // Nothing escapes main (clang-tidy bugprone-exception-escape): an error while reporting an
  // error (stderr closed or full: fmt::print throws) or while setting up still exits 3.
  try {
    return run_main(argc, argv);
  } catch (...) {
    return static_cast<int>(gm::ExitCode::InternalError);
  }
}
