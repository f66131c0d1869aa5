// gmotion run — placeholder until its stage lands (replaced by the owner of that stage).
#include "cli/commands.hpp"

namespace gm::cli {

void add_run(CLI::App& app, Context& ctx) {
  auto* sub = app.add_subcommand("run", "(not yet available)");
  sub->callback([&ctx] { ctx.exit_code = 3; });
}

}  // namespace gm::cli
