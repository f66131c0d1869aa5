// Vibration at the tool tip in a run: VibrationMeter by hand, the summary and trace of a mode
// machine.
#include "machine/machine_file.hpp"
#include "measure/run_summary.hpp"
#include "measure/vibration_meter.hpp"
#include "pipeline/run.hpp"
#include "support/repo_root.hpp"
#include "trace/trace_reader.hpp"

#include "support/run_command.hpp"
#include "support/scratch_dir.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// Rows k0.. of one axis into a block.
void rows(gm::SampleBlock& b, std::int64_t k0, const std::vector<std::int64_t>& cmd,
          const std::vector<std::int64_t>& ref, const std::vector<double>& tip,
          const std::vector<double>& defl, int from) {
  b.reset(k0);
  b.count = static_cast<int>(cmd.size()) - from;
  for (int i = 0; i < b.count; ++i) {
    b.cmd_blu.v[0][i] = cmd[static_cast<std::size_t>(from + i)];
    b.ref_blu.v[0][i] = ref[static_cast<std::size_t>(from + i)];
    b.table_blu.v[0][i] = tip[static_cast<std::size_t>(from + i)];
    b.defl_blu.v[0][i] = defl[static_cast<std::size_t>(from + i)];
    b.line[i] = 100 + static_cast<int>(k0) + i;
  }
}

struct Sample {
  std::int64_t cmd, ref;
  double tip;
};

}  // namespace

TEST_CASE("VibrationMeter: stops, windows and the worst stop, worked by hand", "[vibration]") {
  // 3 taps (the output rests 2 samples after the input's last change), T = 10 ms, a window of
  // 50 ms = 5 samples. The input moves at k = 2, 3 (last change at 3, line 103): window
  // k = 5..9. It moves again at k = 12 (line 112): window k = 14..18. Line of row k: 100 + k.
  const std::vector<std::int64_t> cmd = {0,  0,  10, 20, 20, 20, 20, 20, 20, 20,
                                         20, 20, 30, 30, 30, 30, 30, 30, 30, 30};
  std::vector<std::int64_t> ref(20, 20);
  for (int k = 12; k < 20; ++k) ref[static_cast<std::size_t>(k)] = 30;
  std::vector<double> tip(20), defl(20, 0.0);
  for (int k = 0; k < 20; ++k)
    tip[static_cast<std::size_t>(k)] = static_cast<double>(ref[static_cast<std::size_t>(k)]);
  // Window 1: deflection 1, −4, 2, 0, 3 (max 4); tip − ref 0.5, −7, 1, 1, 1 (max 7).
  const double d1[] = {1, -4, 2, 0, 3}, e1[] = {0.5, -7, 1, 1, 1};
  // Window 2: deflection −6, 1, 1, 1, 1 (max 6); tip − ref 2, 2, 2, 2, −3 (max 3).
  const double d2[] = {-6, 1, 1, 1, 1}, e2[] = {2, 2, 2, 2, -3};
  for (int j = 0; j < 5; ++j) {
    defl[static_cast<std::size_t>(5 + j)] = d1[j];
    tip[static_cast<std::size_t>(5 + j)] += e1[j];
    defl[static_cast<std::size_t>(14 + j)] = d2[j];
    tip[static_cast<std::size_t>(14 + j)] += e2[j];
  }
  defl[10] = -50.0;  // outside every window: the path's deflection only
  tip[19] += 100.0;  // after the second window closed: not counted
  gm::VibrationMeter m(1, 3, 0.01, 0.05);
  auto b = std::make_unique<gm::SampleBlock>();
  // Two blocks (the state carries over), the first from row 0, the second k = 8..19.
  rows(*b, 0, std::vector<std::int64_t>(cmd.begin(), cmd.begin() + 8),
       std::vector<std::int64_t>(ref.begin(), ref.begin() + 8),
       std::vector<double>(tip.begin(), tip.begin() + 8),
       std::vector<double>(defl.begin(), defl.begin() + 8), 0);
  m.add_block(*b, 0);
  rows(*b, 8, std::vector<std::int64_t>(cmd.begin() + 8, cmd.end()),
       std::vector<std::int64_t>(ref.begin() + 8, ref.end()),
       std::vector<double>(tip.begin() + 8, tip.end()),
       std::vector<double>(defl.begin() + 8, defl.end()), 0);
  m.add_block(*b, 0);
  m.finish();
  const gm::AxisVibration& x = m.axis(0);
  CHECK(x.stops == 2);
  CHECK(x.residual_blu == 6.0);
  CHECK(x.residual_line == 112);
  CHECK(x.residual_t_s == Approx(0.14));
  CHECK(x.settle_blu == 7.0);
  CHECK(x.settle_line == 103);
  CHECK(x.deflection_blu == 50.0);
  CHECK(x.deflection_line == 110);
}

TEST_CASE("a run on a machine with a 40 Hz mode: the summary against the samples by hand",
          "[vibration][summary]") {
  // One 2 mm move at F6000 on X, then a dwell. The settling figure is max |tip − ref| over the
  // 0.2 s after the Acc/Dec output rests, which is 59 samples (60 taps) after the last change
  // of X's interpolator output: computed here from the run's own samples.
  gm::RunOptions o;
  o.config.machine =
      gm::load_machine_file(gm::test::kRepoRoot / "programs/machines/ringing-40hz.toml");
  o.program_name = "tiny.nc";
  o.consumer_thread = false;
  const std::string trace = (gmtest::scratch_dir("vibration") / "tiny.csv").string();
  o.trace_path = trace;
  std::istringstream in("G21 G90 G94\nG1 X2 F6000\nG4 P0.4\nM2\n");
  gm::Run run(std::move(o), in, gm::InterpreterOptions{});
  std::vector<Sample> s;
  while (run.step() == gm::RunStatus::Working)
    s.push_back({run.last().cmd_blu[0], run.last().ref_blu[0], run.last().table_blu[0]});
  REQUIRE(run.summary().vibration() != nullptr);
  std::size_t last_change = 0;
  for (std::size_t k = 1; k < s.size(); ++k)
    if (s[k].cmd != s[k - 1].cmd) last_change = k;
  const std::size_t rest = last_change + 59;
  REQUIRE(rest + 200 <= s.size());
  CHECK(s[rest].ref == 2000);
  CHECK(s[rest - 1].ref != 2000);  // the output comes to rest exactly there
  double settle = 0.0, ring = 0.0;
  for (std::size_t k = rest; k < rest + 200; ++k)
    settle = std::max(settle, std::abs(s[k].tip - static_cast<double>(s[k].ref)));
  for (std::size_t k = rest + 100; k < rest + 200; ++k)
    ring = std::max(ring, std::abs(s[k].tip - 2000.0));
  const gm::AxisVibration& x = run.summary().vibration()->axis(0);
  CHECK(x.stops == 1);
  CHECK(x.settle_blu == settle);
  CHECK(x.settle_line == 2);
  CHECK(x.residual_line == 2);
  CHECK(x.residual_t_s == Approx(static_cast<double>(rest) * 0.001));
  // The residual vibration is the mode's deflection; the tip still rings 0.1 s on (ζ = 0.02).
  CHECK(x.residual_blu > 1.0);
  CHECK(ring > 1.0);
  CHECK(run.summary().vibration()->axis(2).residual_blu == 0.0);  // Z has no mode
  const std::string json = run.summary().json();
  CHECK(json.find("\"vibration\":{\"contour_measured_at\":\"tool tip\"") != std::string::npos);
  CHECK(run.summary().text().find("measured at the tool tip") != std::string::npos);
  // The trace has the tip; its x_tip is the samples' table position.
  gm::TraceReader r(trace);
  const auto& cols = r.columns();
  const auto at = std::find(cols.begin(), cols.end(), "x_tip");
  REQUIRE(at != cols.end());
  const auto ix = static_cast<std::size_t>(at - cols.begin());
  std::vector<double> v;
  for (std::size_t k = 0; k < s.size(); ++k) {
    REQUIRE(r.next(v));
    if (std::abs(v[ix] - s[k].tip) > 0.0005 + 1e-9) FAIL("x_tip differs at sample " << k);
  }
}

TEST_CASE("without modes: no tip column, no vibration in the summary", "[vibration][summary]") {
  gm::RunOptions o;
  o.config.machine =
      gm::load_machine_file(gm::test::kRepoRoot / "programs/machines/default-ff.toml");
  o.program_name = "tiny.nc";
  o.consumer_thread = false;
  const std::string trace = (gmtest::scratch_dir("vibration") / "plain.csv").string();
  o.trace_path = trace;
  std::istringstream in("G21 G90 G94\nG1 X2 F6000\nM2\n");
  gm::Run run(std::move(o), in, gm::InterpreterOptions{});
  while (run.step() == gm::RunStatus::Working) {
  }
  CHECK(run.summary().vibration() == nullptr);
  CHECK(run.summary().json().find("vibration") == std::string::npos);
  CHECK(run.summary().text().find("tool tip") == std::string::npos);
  gm::TraceReader r(trace);
  for (const std::string& c : r.columns()) CHECK(c.find("tip") == std::string::npos);
  CHECK(r.header_value("units").find("tip") == std::string::npos);
}

TEST_CASE("gmotion compare: the tool tip columns are the runs' summaries", "[vibration][compare]") {
  // Each row's residual vibration and settling are the worst axis's of `gmotion run` with that
  // profile and tau; the cycle time is the run's.
  const std::string repo = gm::test::kRepoRoot.string();
  const std::string machine = repo + "/programs/machines/ringing-40hz.toml";
  const std::string program = repo + "/programs/ringing.nc";
  const auto c =
      gmtest::run_gmotion("compare " + program + " --machine " + machine +
                          " --profiles linear,linear+zv:40@0.02 --taus 0.06,0.073 --json");
  REQUIRE(c.code == 0);
  const std::regex row(
      R"re("profile":"([^"]+)".*?"cycle_time_s":([0-9.e+-]+).*?"tau_s":([0-9.e+-]+),"residual_vibration_max_blu":([0-9.e+-]+),"settle_max_blu":([0-9.e+-]+))re");
  const std::regex run_residual(R"("residual_max_blu":\{"value":([0-9.e+-]+))");
  const std::regex run_settle(R"("settle_max_blu":\{"value":([0-9.e+-]+))");
  const std::regex run_cycle(R"("cycle_time_s":([0-9.e+-]+))");
  int rows = 0;
  for (auto it = std::sregex_iterator(c.out.begin(), c.out.end(), row);
       it != std::sregex_iterator(); ++it, ++rows) {
    const std::smatch& m = *it;
    const std::string json = (gmtest::scratch_dir("vibration") / "cmp.json").string();
    REQUIRE(gmtest::run_gmotion("run " + program + " --machine " + machine + " --profile " +
                                m[1].str() + " --tau " + m[3].str() + " --summary-json " + json)
                .code == 0);
    std::ifstream in(json);
    const std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    double residual = 0, settle = 0;
    for (auto r = std::sregex_iterator(s.begin(), s.end(), run_residual);
         r != std::sregex_iterator(); ++r)
      residual = std::max(residual, std::stod((*r)[1].str()));
    for (auto r = std::sregex_iterator(s.begin(), s.end(), run_settle); r != std::sregex_iterator();
         ++r)
      settle = std::max(settle, std::stod((*r)[1].str()));
    std::smatch cyc;
    REQUIRE(std::regex_search(s, cyc, run_cycle));
    INFO(m[1].str());
    CHECK(std::stod(m[4].str()) == Approx(residual).epsilon(1e-5));
    CHECK(std::stod(m[5].str()) == Approx(settle).epsilon(1e-5));
    CHECK(std::stod(m[2].str()) == Approx(std::stod(cyc[1].str())).epsilon(1e-6));
    CHECK(residual > 1.0);
  }
  CHECK(rows == 2);
  // The program has no arcs: the radius figures are JSON nulls and "-" in the table, not "nan".
  CHECK(c.out.find("nan") == std::string::npos);
  CHECK(c.out.find("\"total_blu\":null") != std::string::npos);
  const auto table = gmtest::run_gmotion("compare " + program + " --machine " + machine +
                                         " --profiles linear --taus 0.06");
  REQUIRE(table.code == 0);
  CHECK(table.out.find("nan") == std::string::npos);
  // The default machine has no modes: no such columns.
  const auto plain = gmtest::run_gmotion("compare " + repo + "/programs/square.nc --json");
  REQUIRE(plain.code == 0);
  CHECK(plain.out.find("residual_vibration") == std::string::npos);
}
