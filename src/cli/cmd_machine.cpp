// gmotion machine export: a machine (TOML or LinuxCNC INI) written as TOML or as INI sections.
#include "cli/commands.hpp"
#include "cli/settings_flags.hpp"
#include "common/status.hpp"
#include "machine/linuxcnc_ini.hpp"
#include "machine/machine_file.hpp"

#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <memory>

namespace gm::cli {

void add_machine(CLI::App& app, Context& ctx) {
  auto* sub = app.add_subcommand("machine", "Machine files: export one as TOML or LinuxCNC INI");
  sub->require_subcommand(1);
  struct Opts {
    setup::RunSettings machine;  ///< the machine choice
    bool linuxcnc = false;
    std::string out;
  };
  auto o = std::make_shared<Opts>();
  auto* ex = sub->add_subcommand(
      "export",
      "Write the machine (--machine, flags applied) as a complete TOML machine file, or "
      "with --linuxcnc as the matching LinuxCNC INI sections");
  add_setting_flags(ex, o->machine, setup::kMachineGroup);
  ex->add_flag("--linuxcnc", o->linuxcnc,
               "Write LinuxCNC INI sections ([EMCMOT] [TRAJ] [KINS] [AXIS_*] [JOINT_*])");
  ex->add_option("-o,--output", o->out, "Write here instead of stdout");
  ex->callback([o, &ctx] {
    const Machine m = setup::resolve_machine(o->machine);
    const std::string text = o->linuxcnc ? machine_to_linuxcnc_ini(m) : machine_to_toml(m);
    if (o->out.empty()) {
      std::cout << text;
    } else {
      std::ofstream f(o->out, std::ios::binary);
      f << text;
      if (!f) throw InputError(fmt::format("cannot write '{}'", o->out));
    }
    ctx.exit_code = 0;
  });
}

}  // namespace gm::cli
