// Feed override through the whole pipeline: steps follow the filter's step response (Eq. 1),
// holds lose no position, M48/M49/M50 switch it, record -> replay is byte-identical.
#include "accdec/taps.hpp"
#include "interp/program.hpp"
#include "machine/machine_file.hpp"
#include "override/override_schedule.hpp"
#include "pipeline/pipeline.hpp"
#include "support/run_command.hpp"
#include "support/sample_stepper.hpp"
#include "support/scratch_dir.hpp"
#include "support/test_scale.hpp"

#include <fmt/format.h>
#include <catch2/catch.hpp>

#include <unistd.h>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// Runs `program` with servo off; `scale(k)` gives the feed override for sample k.
std::vector<gm::SampleRecord> run(const std::string& program, const std::string& profile,
                                  const std::function<double(std::int64_t)>& scale,
                                  gm::AxisBlu* end = nullptr, double tau_s = 0.164) {
  gm::Machine m = gm::default_machine();
  m.profile = profile;
  m.tau_s = tau_s;
  std::istringstream in(program);
  gm::InterpreterOptions opts;
  opts.machine = &m;
  gm::ProgramStream stream(in, "t.nc", opts);
  gm::RunConfig cfg;
  cfg.machine = m;
  cfg.servo = false;
  gmtest::SampleStepper p(cfg, stream);
  std::vector<gm::SampleRecord> out;
  gm::SampleRecord rec;
  for (std::int64_t k = 0;; ++k) {
    gm::OverrideInput ovr;
    ovr.feed_scale = scale(k);
    if (p.step(ovr, rec) != gm::PipelineStatus::Working) break;
    out.push_back(rec);
    REQUIRE(k < 200000);
  }
  if (end) *end = p.program_end_blu();
  return out;
}

const fs::path kRepo = fs::path(GMOTION_TESTS_DIR).parent_path();

}  // namespace

TEST_CASE("override steps 100 -> 50 -> 150 % follow the filter's step response exactly (Eq. 1)") {
  // F600 = 10 mm/s = 40 BLU per 4 ms sample along X; 50 % = 20, 150 % = 60 BLU per sample.
  const std::string program = "G21 G90 G64\nG1 X100 F600\nM2\n";
  const std::int64_t k0 = 100, k1 = 200;
  for (const char* profile : {"linear", "blackman", "scurve2"}) {
    INFO(profile);
    const gm::Taps taps = gm::design_taps(profile, 0.164, 0.004);
    const auto s = run(program, profile, [&](std::int64_t k) {
      return k < k0 ? 1.0 : k < k1 ? 0.5 : 1.5;
    });
    REQUIRE(s.size() > static_cast<std::size_t>(k1 + 60));
    // Closed form: V'[k] = (1/b_s) Σ b_i V[k−i] for the input V stepping at k0 and at k1.
    auto v_in = [&](std::int64_t k) { return k < k0 ? 40.0 : k < k1 ? 20.0 : 60.0; };
    for (std::int64_t k = k0 - 5; k < k1 + 60; ++k) {
      double v = 0.0;
      for (std::size_t i = 0; i < taps.integer.size(); ++i)
        v += static_cast<double>(taps.integer[i]) * v_in(k - static_cast<std::int64_t>(i));
      v /= static_cast<double>(taps.b_s);
      const double got = static_cast<double>(s[static_cast<std::size_t>(k)].ref_blu[0] -
                                             s[static_cast<std::size_t>(k - 1)].ref_blu[0]);
      INFO("k = " << k);
      CHECK(std::abs(got - v) <= 1.0);  // the output position is rounded to whole BLU
      CHECK(s[static_cast<std::size_t>(k)].ref_blu[1] == 0);
    }
  }
}

TEST_CASE("a hold stops the output within N+1 samples, keeps the position and resumes exactly") {
  const gm::Taps taps = gm::design_taps("blackman", 0.164, 0.004);
  const std::int64_t n = static_cast<std::int64_t>(taps.integer.size());
  gm::AxisBlu end = gm::AxisBlu::Zero();
  const auto s = run(
      "G21 G90 G64\nG1 X20 Y10 F1200\nM2\n", "blackman",
      [](std::int64_t k) { return k >= 50 && k < 300 ? 0.0 : 1.0; }, &end);
  // The interpolator holds from sample 50: the filter output is still from sample 50 + N.
  for (std::int64_t k = 50 + n; k < 300; ++k) {
    INFO("k = " << k);
    CHECK(s[static_cast<std::size_t>(k)].ref_blu ==
          s[static_cast<std::size_t>(50 + n - 1)].ref_blu);
    CHECK((s[static_cast<std::size_t>(k)].events & gm::kEventHold) != 0);
  }
  CHECK(s.back().ref_blu == end);
  CHECK(end == gm::blu3(20000, 10000, 0));
  // Resumed: the cycle is longer than without the hold by the 250 held samples exactly.
  const auto free_run =
      run("G21 G90 G64\nG1 X20 Y10 F1200\nM2\n", "blackman", [](std::int64_t) { return 1.0; });
  CHECK(s.size() == free_run.size() + 250);
}

TEST_CASE("M49 and M50 P0 disable the override, M48 and M50 P1 enable it again") {
  // 0.5 override all along; line 3 runs at 100 % (disabled), line 5 at 50 % (enabled).
  const std::string program =
      "G21 G90 G64 F600\nM49\nG1 X10\nM48\nG1 X20\nM50 P0\nG1 X30\nM50 P1\nG1 X40\nM2\n";
  const auto s = run(program, "linear", [](std::int64_t) { return 0.5; });
  auto step_on_line = [&](int line) {
    for (std::size_t k = 60; k < s.size(); ++k)
      if (s[k].line == line && s[k - 1].line == line) return s[k].cmd_blu[0] - s[k - 1].cmd_blu[0];
    return std::int64_t{-1};
  };
  CHECK(step_on_line(3) == 40);
  CHECK(step_on_line(5) == 20);
  CHECK(step_on_line(7) == 40);
  CHECK(step_on_line(9) == 20);
}

TEST_CASE("record -> replay gives a byte-identical trace (schedule and live input)") {
  const fs::path dir = gmtest::scratch_dir("ovr");
  const std::string prog = (kRepo / "programs" / "override-replay.nc").string();
  const std::string sched = (kRepo / "programs" / "override-replay.csv").string();
  const std::string rec = (dir / "rec.csv").string(), a = (dir / "a.csv").string(),
                    b = (dir / "b.csv").string();
  REQUIRE(gmtest::run_gmotion("run " + prog + " --override-file " + sched + " --record-override " +
                              rec + " --trace " + a)
              .code == 0);
  REQUIRE(gmtest::run_gmotion("run " + prog + " --override-file " + rec + " --trace " + b).code ==
          0);
  CHECK(gmtest::sh("cmp " + a + " " + b).code == 0);

  // Live: typed lines on stdin while the run is paced at wall-clock speed.
  const std::string live_prog = (dir / "short.nc").string();
  std::ofstream(live_prog) << "G21 G90 G64\nG1 X5 F1200\nM2\n";
  REQUIRE(gmtest::sh("(sleep 0.1; echo 50; sleep 0.1; echo rapid 25) | " +
                     std::string(GMOTION_BIN) + " run " + live_prog +
                     " --realtime --record-override " + rec + " --trace " + a + " >/dev/null 2>&1")
              .code == 0);
  REQUIRE(
      gmtest::run_gmotion("run " + live_prog + " --override-file " + rec + " --trace " + b).code ==
      0);
  CHECK(gmtest::sh("cmp " + a + " " + b).code == 0);
  CHECK(gmtest::sh("grep -c ',50$' " + rec).out == "1\n");  // the typed 50 % was recorded once
  fs::remove_all(dir);
}

TEST_CASE("override CLI errors: bad schedule, out of range, endless hold, --max-time") {
  const fs::path dir = gmtest::scratch_dir("ovr-err");
  const std::string prog = (kRepo / "programs" / "square.nc").string();
  const std::string bad = (dir / "bad.csv").string();
  std::ofstream(bad) << "0,100\n1.0,fast\n";
  auto r = gmtest::run_gmotion("run " + prog + " --override-file " + bad);
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains(bad + ":2: 'fast' is not a percentage"));

  r = gmtest::run_gmotion("run " + prog + " --override 201");
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("--override 201 is outside 0..200 %"));

  const std::string hold = (dir / "hold.csv").string();
  std::ofstream(hold) << "1.0,0\n";
  const std::string trace = (dir / "t.csv").string();
  r = gmtest::run_gmotion("run " + prog + " --override-file " + hold + " --trace " + trace);
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("nothing in the override schedule resumes it"));
  CHECK_FALSE(fs::exists(trace));
  CHECK_FALSE(fs::exists(trace + ".partial"));

  r = gmtest::run_gmotion("run " + prog + " --max-time 0.5 --trace " + trace);
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("run stopped at --max-time 0.5 s"));
  CHECK_FALSE(fs::exists(trace));
  CHECK_FALSE(fs::exists(trace + ".partial"));
  fs::remove_all(dir);
}

TEST_CASE(
    "property: random programs x random schedules x every profile end exactly, never speed up") {
  const char* env = std::getenv("GMOTION_SEED");
  const std::uint64_t seed = env ? std::strtoull(env, nullptr, 10) : 20261122u;
  const int programs = env ? 1 : gmtest::scaled(1000);
  std::mt19937_64 rng(seed);
  const std::vector<std::pair<std::string, double>> profiles = {
      {"linear", 0.164},   {"scurve1", 0.164}, {"scurve2", 0.164},
      {"blackman", 0.164}, {"hann", 0.1},      {"cascade:10,5", 0.056}};
  const double levels[] = {0.0, 0.25, 0.5, 1.0, 1.5, 2.0};
  for (int p = 0; p < programs; ++p) {
    const std::uint64_t program_seed = env ? seed : rng();
    std::mt19937_64 prng(program_seed);
    auto pu = [&](double a, double b) {
      return std::uniform_real_distribution<double>(a, b)(prng);
    };
    // A short program of lines and IJK arcs in XY (Z for the odd helix-free line).
    std::string text = "G21 G90 G64 G17\n";
    double x = 0, y = 0;
    const int blocks = 2 + static_cast<int>(pu(0, 4));
    for (int b = 0; b < blocks; ++b) {
      const double f = pu(100, 3000);
      if (pu(0, 1) < 0.5) {
        x = pu(-10, 10), y = pu(-10, 10);
        text += fmt::format("G1 X{:.4f} Y{:.4f} Z{:.4f} F{:.1f}\n", x, y, pu(-1, 1), f);
      } else {
        const double i = pu(-3, 3), j = pu(-3, 3), r = std::hypot(i, j), phi = pu(-M_PI, M_PI);
        const double cx = x + i, cy = y + j;
        x = cx + r * std::cos(phi), y = cy + r * std::sin(phi);
        text += fmt::format("G{} X{:.6f} Y{:.6f} I{:.6f} J{:.6f} F{:.1f}\n", pu(0, 1) < 0.5 ? 2 : 3,
                            x, y, i, j, f);
      }
    }
    text += "M2\n";
    // A schedule: a step every 10..80 samples, ending on a non-zero level (so holds resume).
    std::vector<std::pair<std::int64_t, double>> steps;
    for (std::int64_t k = static_cast<std::int64_t>(pu(0, 50)); steps.size() < 8;
         k += 10 + static_cast<std::int64_t>(pu(0, 70)))
      steps.emplace_back(k, levels[static_cast<int>(pu(0, 6))]);
    steps.emplace_back(steps.back().first + 20, 1.0);
    auto scale = [&](std::int64_t k) {
      double s = 1.0;
      for (const auto& [at, level] : steps)
        if (k >= at) s = level;
      return s;
    };
    for (const auto& [profile, tau] : profiles) {
      INFO("seed " << program_seed << " (GMOTION_SEED=" << program_seed << " replays it), profile "
                   << profile << "\nprogram:\n"
                   << text);
      gm::AxisBlu end = gm::AxisBlu::Zero();
      const auto s = run(text, profile, scale, &end, tau);
      REQUIRE(!s.empty());
      CHECK(s.back().ref_blu == end);
      const std::size_t n = gm::design_taps(profile, tau, 0.004).integer.size();
      // Per-sample steps of the interpolator (input) and of the Acc/Dec output; the program
      // starts at the origin, so sample 0's step is from zero.
      std::vector<double> in_speed(s.size(), 0.0);
      bool ok = true;
      for (std::size_t k = 0; k < s.size() && ok; ++k) {
        const gm::AxisBlu prev_cmd = k ? s[k - 1].cmd_blu : gm::AxisBlu::Zero();
        const gm::AxisBlu prev_ref = k ? s[k - 1].ref_blu : gm::AxisBlu::Zero();
        in_speed[k] = (s[k].cmd_blu - prev_cmd).cast<double>().norm();
        double max_in = 0.0;
        for (std::size_t i = k + 1 >= n ? k + 1 - n : 0; i <= k; ++i)
          max_in = std::max(max_in, in_speed[i]);
        const double out = (s[k].ref_blu - prev_ref).cast<double>().norm();
        ok = out <= max_in + std::sqrt(3.0) + 1e-9 && std::isfinite(s[k].contour_err_blu);
        if (!ok) INFO("sample " << k << ": output step " << out << " BLU > input max " << max_in);
      }
      CHECK(ok);
    }
  }
}

TEST_CASE("override steps 100 -> 50 -> 150 % in the middle of an arc: geometry and filter exact") {
  // A full circle of R = 10 mm about (10, 0), starting at the origin, ccw at F1200 (20 mm/s).
  const std::string program = "G21 G90 G64 G17\nG3 X0 Y0 I10 J0 F1200\nM2\n";
  const std::int64_t k0 = 100, k1 = 200;
  auto scale = [&](std::int64_t k) { return k < k0 ? 1.0 : k < k1 ? 0.5 : 1.5; };
  for (const char* profile : {"linear", "blackman"}) {
    INFO(profile);
    const gm::Taps taps = gm::design_taps(profile, 0.164, 0.004);
    const auto s = run(program, profile, scale);
    // The interpolator: arc length advances by 20 mm/s · scale · T each sample (independent sum).
    double arc_mm = 0.0;
    const double length = 2 * M_PI * 10;
    for (std::size_t k = 0; k < s.size() && arc_mm < length - 0.2; ++k) {
      arc_mm += 20.0 * scale(static_cast<std::int64_t>(k)) * 0.004;
      const double th = M_PI + arc_mm / 10.0;
      INFO("k = " << k);
      CHECK(std::abs(static_cast<double>(s[k].cmd_blu[0]) -
                     1000.0 * (10.0 + 10.0 * std::cos(th))) <= 1.0);
      CHECK(std::abs(static_cast<double>(s[k].cmd_blu[1]) - 1000.0 * (10.0 * std::sin(th))) <= 1.0);
    }
    // The Acc/Dec output is Eq. 1 on positions (Eq. 12): Σ b_i cmd[k−i] / b_s, the origin before.
    for (std::size_t k = 0; k < s.size(); ++k) {
      for (int a = 0; a < 2; ++a) {
        double acc = 0.0;
        for (std::size_t i = 0; i < taps.integer.size(); ++i)
          acc += static_cast<double>(taps.integer[i]) *
                 (k >= i ? static_cast<double>(s[k - i].cmd_blu[a]) : 0.0);
        INFO("k = " << k << " axis " << a);
        CHECK(std::abs(static_cast<double>(s[k].ref_blu[a]) -
                       acc / static_cast<double>(taps.b_s)) <= 0.5 + 1e-9);
      }
    }
  }
}
