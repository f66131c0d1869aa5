// gmotion check PROGRAM: validates a G-code program, printing every error or a one-line summary.
#include "cli/commands.hpp"
#include "cli/settings_flags.hpp"
#include "common/status.hpp"
#include "interp/program.hpp"
#include "setup/program_input.hpp"

#include <fmt/format.h>

#include <iostream>
#include <map>
#include <memory>

namespace gm::cli {

void add_check(CLI::App& app, Context& ctx) {
  auto* sub = app.add_subcommand(
      "check", "Validate a G-code program: every error (file:line:col), or a summary");
  struct Opts {
    std::string program;
    setup::RunSettings settings;  ///< the machine file, axes, tools, block delete, language
    std::string arc_rule;
  };
  auto opts = std::make_shared<Opts>();
  sub->add_option("PROGRAM", opts->program, "G-code file ('-' reads stdin)")->required();
  add_setting_flags(sub, opts->settings, setup::kProgramGroup | setup::kLanguageGroup);
  sub->add_option("--arc-rule", opts->arc_rule, "arc end-radius tolerance rule")
      ->check(CLI::IsMember({"linuxcnc", "grbl", "g2core"}));
  sub->callback([opts, &ctx] {
    Machine machine = setup::resolve_machine(opts->settings, setup::IniNotes::Quiet);
    if (!opts->arc_rule.empty()) {
      static const std::map<std::string, ArcRule> rules{
          {"linuxcnc", ArcRule::LinuxCnc}, {"grbl", ArcRule::Grbl}, {"g2core", ArcRule::G2core}};
      machine.arc_rule = rules.at(opts->arc_rule);
    }
    const InterpreterOptions io = setup::interpreter_options(opts->settings, machine);
    std::cout.flush();
    setup::ProgramInput program(opts->program);
    const CheckSummary s = check_program(program.rewind(), program.name(), io, std::cerr);
    if (s.errors > 0) {
      fmt::print(stderr, "{}: {} error{}\n", opts->program == "-" ? "<stdin>" : opts->program,
                 s.errors, s.errors == 1 ? "" : "s");
      ctx.exit_code = static_cast<int>(ExitCode::InputError);
      return;
    }
    fmt::print(
        "{}: ok: {} blocks, {} moves, path {:.3f} mm, {:.3f} s at programmed feed (rapids at {:g} "
        "mm/min); tool table {}\n",
        opts->program == "-" ? "<stdin>" : opts->program, s.blocks, s.moves, s.path_length_mm,
        s.time_at_feed_s, machine.rapid_mm_min, machine.tool_table.source);
    ctx.exit_code = 0;
  });
}

}  // namespace gm::cli
