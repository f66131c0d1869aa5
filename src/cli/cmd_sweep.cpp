// gmotion sweep SPEC.toml: the runs of a spec on local cores, or emitted for GNU parallel/Slurm.
#include "cli/commands.hpp"
#include "common/status.hpp"
#include "sweep/sweep_runner.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

namespace gm::cli {
namespace {

void sweep_write_file(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
  if (!f) throw InputError(fmt::format("cannot write '{}'", path));
}

std::string sweep_self_exe() {
  std::error_code ec;
  const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("gmotion") : p.string();
}

}  // namespace

void add_sweep(CLI::App& app, Context& ctx) {
  struct Opts {
    std::string spec, csv, json, emit, out_dir = "sweep-runs", merge_dir, gmotion;
    int jobs = 0;
  };
  auto o = std::make_shared<Opts>();
  auto* sub = app.add_subcommand(
      "sweep",
      "Run programs x machines x profiles x tau x overrides (a TOML spec) and write one "
      "table, a row per run (docs/sweeps.md)");
  sub->add_option("spec", o->spec, "Sweep spec (TOML)")->required();
  sub->add_option("--csv", o->csv, "Write the table as CSV here (default: stdout)");
  sub->add_option("--json", o->json, "Write the table as JSON here");
  sub->add_option("-j,--jobs", o->jobs, "Threads (default: the spec's jobs, else every core)")
      ->check(CLI::Range(0, 1024));
  sub->add_option("--emit", o->emit,
                  "Print the runs for a scheduler instead: 'parallel' (one gmotion run command a "
                  "line, for GNU parallel) or 'slurm' (an sbatch job-array script)")
      ->check(CLI::IsMember({"parallel", "slurm"}));
  sub->add_option("--out-dir", o->out_dir,
                  "With --emit: where the emitted runs write their summaries (run-NNNNN.json)");
  sub->add_option("--merge", o->merge_dir,
                  "Build the table from the summaries in this directory (after --emit's runs)");
  sub->add_option("--gmotion", o->gmotion,
                  "With --emit: the gmotion the commands call (default: this executable)");
  sub->callback([o, &ctx] {
    const sweep::SweepSpec spec = sweep::load_sweep_spec(o->spec);
    if (!o->emit.empty()) {
      const std::string exe = o->gmotion.empty() ? sweep_self_exe() : o->gmotion;
      const auto points = sweep::expand(spec);
      std::error_code ec;
      std::filesystem::create_directories(o->out_dir, ec);
      if (o->emit == "slurm") {
        fmt::print(
            "#!/bin/bash\n#SBATCH --job-name=gmotion-sweep\n#SBATCH --array=0-{}\n"
            "#SBATCH --cpus-per-task=1\n# then: gmotion sweep {} --merge {} --csv table.csv\n"
            "case \"$SLURM_ARRAY_TASK_ID\" in\n",
            points.size() - 1, o->spec, o->out_dir);
        for (const auto& r : points)
          fmt::print("{}) {} ;;\n", r.index, sweep::run_command(spec, r, exe, o->out_dir));
        fmt::print("esac\n");
      } else {
        for (const auto& r : points)
          fmt::print("{}\n", sweep::run_command(spec, r, exe, o->out_dir));
      }
      ctx.exit_code = 0;
      return;
    }
    std::vector<sweep::SweepRow> rows;
    if (!o->merge_dir.empty()) {
      rows = sweep::merge(spec, o->merge_dir);
    } else {
      const std::size_t total = sweep::expand(spec).size();
      rows = sweep::run_local(spec, o->jobs, [total](const sweep::SweepRow& r) {
        fmt::print(stderr, "[{}/{}] {} {} {} tau {} override {}: {}\n", r.index + 1, total,
                   r.program, r.machine, r.profile, r.tau_s, r.override_, r.status);
      });
    }
    const std::string csv = sweep::to_csv(rows);
    if (o->csv.empty())
      std::cout << csv;
    else
      sweep_write_file(o->csv, csv);
    if (!o->json.empty()) sweep_write_file(o->json, sweep::to_json(rows));
    int bad = 0;
    for (const auto& r : rows) bad += r.status == "ok" ? 0 : 1;
    if (bad > 0) fmt::print(stderr, "gmotion sweep: {} of {} runs not ok\n", bad, rows.size());
    ctx.exit_code = bad > 0 ? static_cast<int>(ExitCode::InputError) : 0;
  });
}

}  // namespace gm::cli
