// gmotion check PROGRAM: validates a G-code program, printing every error or a one-line summary.
#include "cli/commands.hpp"
#include "cli/language_flags.hpp"
#include "cli/run_setup.hpp"
#include "common/status.hpp"
#include "interp/program.hpp"
#include "machine/machine_file.hpp"

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
    std::string machine_file;
    std::string tool_table;
    std::string user_mcode_dir;
    std::string axes;
    bool block_delete = false;
    std::string arc_rule;
    LanguageFlags language;
  };
  auto opts = std::make_shared<Opts>();
  sub->add_option("PROGRAM", opts->program, "G-code file ('-' reads stdin)")->required();
  sub->add_option("--machine", opts->machine_file, "machine description file (TOML)");
  sub->add_option("--axes", opts->axes, kAxesFlagHelp);
  sub->add_option("--tool-table", opts->tool_table,
                  "LinuxCNC tool table (T1 P1 Z50 D6 ;comment), mm; default: the machine's");
  sub->add_option("--user-mcode-dir", opts->user_mcode_dir, kUserMcodeDirHelp);
  sub->add_flag("--block-delete", opts->block_delete, "skip lines that start with '/'");
  add_language_flags(sub, opts->language);
  sub->add_option("--arc-rule", opts->arc_rule, "arc end-radius tolerance rule")
      ->check(CLI::IsMember({"linuxcnc", "grbl", "g2core"}));
  sub->callback([opts, &ctx] {
    Machine machine;
    if (!opts->machine_file.empty()) machine = load_machine_file(opts->machine_file);
    apply_axes_flag(machine, opts->axes);
    if (!opts->tool_table.empty()) machine.tool_table = load_tool_table(opts->tool_table);
    if (!opts->user_mcode_dir.empty()) machine.user_mcode_dir = opts->user_mcode_dir;
    if (!opts->arc_rule.empty()) {
      static const std::map<std::string, ArcRule> rules{
          {"linuxcnc", ArcRule::LinuxCnc}, {"grbl", ArcRule::Grbl}, {"g2core", ArcRule::G2core}};
      machine.arc_rule = rules.at(opts->arc_rule);
    }
    InterpreterOptions io{&machine, opts->block_delete};
    apply_language_flags(opts->language, machine, io);
    std::cout.flush();
    ProgramInput program(opts->program);
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
