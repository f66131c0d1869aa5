// gmotion run: the whole pipeline on a program, streaming a trace and printing a summary.
#include "cli/commands.hpp"
#include "cli/run_flags.hpp"

#include <memory>

namespace gm::cli {

void add_run(CLI::App& app, Context& ctx) {
  auto flags = std::make_shared<RunFlags>();
  auto* sub = app.add_subcommand("run", "Run the whole pipeline on a program: trace and summary");
  add_run_flags(sub, *flags);
  sub->callback([flags, &ctx] {
    validate_run_flags(*flags);
    ctx.exit_code = run_with_flags(*flags, ctx);
  });
}

}  // namespace gm::cli
