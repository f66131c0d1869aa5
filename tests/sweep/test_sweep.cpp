// gmotion sweep: one row per run with closed-form times; emitted runs merge to the same table.
#include "sweep/sweep_runner.hpp"

#include "support/read_file.hpp"
#include "support/run_command.hpp"
#include "support/scratch_dir.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;
using Catch::Detail::Approx;

namespace {

void write(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

// Two straight feeds (10 mm at 600 mm/min: 1 s at 100 %) and a program with an error; a spec
// of them x two profiles x two τ x two overrides (16 + 8 runs).
fs::path make_spec() {
  const fs::path d = gmtest::scratch_dir("sweep");
  write(d / "line.nc", "(one 10 mm feed)\nG21 G90 G94\nG1 X10 F600\nM2\n");
  write(d / "diagonal.nc", "(6-8-10 triangle leg)\nG21 G90 G94\nG1 X6 Y8 F600\nM2\n");
  write(d / "broken.nc", "G21 G90\nG1 X10 F600 G0\nM2\n");
  write(d / "small.toml", R"(# the CLI's sweep: 2 programs x 2 profiles x 2 overrides
programs = ["line.nc", "broken.nc"]
profiles = ["linear", "blackman"]
tau_s = [0.064]
overrides = [100, 50]
servo = false
)");
  write(d / "spec.toml", R"(# the sweep of test_sweep.cpp
programs = ["line.nc", "diagonal.nc", "broken.nc"]
profiles = ["linear", "blackman"]
tau_s = [0.064, 0.128]
overrides = [100, 50]
servo = false
jobs = 2
)");
  return d;
}

}  // namespace

TEST_CASE("sweep: a row per run, in order, with closed-form program times") {
  const fs::path d = make_spec();
  const gm::sweep::SweepSpec spec = gm::sweep::load_sweep_spec(d / "spec.toml");
  const auto rows = gm::sweep::run_local(spec, 0, {});
  REQUIRE(rows.size() == 3 * 2 * 2 * 2);
  for (std::size_t i = 0; i < 16; ++i) {
    const auto& r = rows[i];
    INFO("row " << i << " " << r.program << " " << r.profile << " " << r.tau_s << " " << r.override_
                << " " << r.error);
    CHECK(r.index == i);
    CHECK(r.status == "ok");
    CHECK(r.program == (i < 8 ? "line.nc" : "diagonal.nc"));
    CHECK(r.profile == ((i / 4) % 2 == 0 ? "linear" : "blackman"));
    CHECK(r.tau_s == ((i / 2) % 2 == 0 ? 0.064 : 0.128));
    // 10 mm at 10 mm/s: 1 s of interpolation (at 50 % override 2 s), to a period T = 4 ms. With
    // ideal axes (servo = false) the run ends when the filter has flushed, tau - T later; the box
    // filter's output moves until then, the Blackman's end taps are ~0 so its motion ends sooner.
    const double t = r.override_ == "100" ? 1.0 : 2.0;
    CHECK(r.cycle_time_s == Approx(t + r.tau_s - 0.004).margin(0.0041));
    if (r.profile == "linear") {
      CHECK(r.program_time_s == Approx(r.cycle_time_s).margin(0.0041));
    } else {
      CHECK(r.program_time_s > t - 0.0041);
      CHECK(r.program_time_s < r.cycle_time_s - 0.004);
    }
    CHECK(r.samples == static_cast<std::int64_t>(std::llround(r.cycle_time_s / 0.004)));
  }
  // A straight line has no contour error to speak of (within a count).
  CHECK(rows[0].contour_max_mm <= 0.001);
  for (std::size_t i = 16; i < 24; ++i) {
    CHECK(rows[i].status == "error");
    CHECK(rows[i].error.find("broken.nc:2") != std::string::npos);
  }
}

TEST_CASE("sweep: the CLI writes CSV and JSON, and emitted commands merge to the same table") {
  const fs::path d = make_spec();
  const std::string spec = (d / "small.toml").string();
  const auto local = gmtest::run_gmotion("sweep " + spec + " --csv " + (d / "local.csv").string() +
                                         " --json " + (d / "local.json").string());
  CHECK(local.code == 1);  // broken.nc's runs are not ok
  CHECK(local.out.find("4 of 8 runs not ok") != std::string::npos);
  const std::string csv = gmtest::slurp(d / "local.csv");
  CHECK(csv.rfind("index,program,machine,profile,tau_s,period_s,override,status,cycle_time_s,",
                  0) == 0);
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 9);
  const std::string json = gmtest::slurp(d / "local.json");
  CHECK(json.find("{\"index\":7,\"program\":\"broken.nc\"") != std::string::npos);

  // The same runs as separate `gmotion run` processes (what GNU parallel or Slurm would start).
  const auto emitted = gmtest::sh(
      std::string(GMOTION_BIN) + " sweep " + spec + " --emit parallel --out-dir " +
      (d / "runs").string() + " > " + (d / "cmds.txt").string() + " && sh " +
      (d / "cmds.txt").string() + " 2>/dev/null; " + GMOTION_BIN + " sweep " + spec + " --merge " +
      (d / "runs").string() + " --csv " + (d / "merged.csv").string() + " 2>/dev/null");
  CHECK(emitted.code == 1);
  const std::string merged = gmtest::slurp(d / "merged.csv");
  // The ok runs agree to the digit; the broken ones wrote no summary.
  std::istringstream a(csv), b(merged);
  std::string la, lb;
  int lines = 0;
  while (std::getline(a, la) && std::getline(b, lb)) {
    if (lines++ <= 4)
      CHECK(la == lb);
    else
      CHECK(lb.find(",missing,") != std::string::npos);
  }
  CHECK(lines == 9);
  const std::string cmds = gmtest::slurp(d / "cmds.txt");
  CHECK(std::count(cmds.begin(), cmds.end(), '\n') == 8);
  CHECK(cmds.find(" run " + (d / "line.nc").string() +
                  " --profile linear --tau 0.064 --override 100 --no-servo") != std::string::npos);
}

TEST_CASE("sweep: a spec error names the file, line and key") {
  const fs::path d = gmtest::scratch_dir("sweep");
  write(d / "bad.toml", "programs = [\"x.nc\"]\ntau_s = [0.1, -1]\n");
  const auto r = gmtest::run_gmotion("sweep " + (d / "bad.toml").string());
  CHECK(r.code == 1);
  CHECK(r.out.find("bad.toml:2: key 'tau_s': each must be > 0 s") != std::string::npos);
}

TEST_CASE("sweep: `flags` gives every run the run settings the lists do not") {
  const fs::path d = gmtest::scratch_dir("sweep");
  write(d / "line.nc", "(one 10 mm feed)\nG21 G90 G94\nG1 X10 F600\nM2\n");
  write(d / "flags.toml",
        "programs = [\"line.nc\"]\nflags = \"--period 0.002 --subroutine-path subs\"\n");
  const gm::sweep::SweepSpec s = gm::sweep::load_sweep_spec(d / "flags.toml");
  CHECK(s.machines[0].machine.period_s == 0.002);  // the machines are resolved with them
  const gm::sweep::RunPoint r = gm::sweep::expand(s)[0];
  CHECK(gm::sweep::run_settings(s, r).subroutine_path == (d / "subs").string());
  CHECK(gm::sweep::run_command(s, r, "gmotion", "out")
            .find(" --period 0.002 --subroutine-path " + (d / "subs").string()) !=
        std::string::npos);
  write(d / "owned.toml", "programs = [\"line.nc\"]\nflags = \"--tau 0.1\"\n");
  const auto owned = gmtest::run_gmotion("sweep " + (d / "owned.toml").string());
  CHECK(owned.code == 1);
  CHECK(owned.out.find("owned.toml:2: key 'flags': --tau: the spec's") != std::string::npos);
}
