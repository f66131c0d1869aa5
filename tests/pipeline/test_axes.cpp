// Up to nine axes: the axis layout, LinuxCNC's feed rule with rotary axes, degrees in
// G20, the missing-axis error, machine files with `axes.letters`, and extra axes that leave X, Y
// and Z sample for sample as they were.
#include "common/status.hpp"
#include "interp/program.hpp"
#include "machine/machine_file.hpp"
#include "motion/geometry.hpp"
#include "pipeline/run.hpp"
#include "support/repo_root.hpp"
#include "support/run_command.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using gm::AxisLayout;
using gm::AxisVec;

namespace {

AxisVec at(std::initializer_list<std::pair<char, double>> values) {
  AxisVec v = AxisVec::Zero();
  for (const auto& [letter, x] : values) v[gm::axis_index(letter)] = x;
  return v;
}

// programs/machines/rotary-a.toml as text.
std::string rotary_a_text() {
  std::ifstream src(gm::test::kRepoRoot / "programs/machines/rotary-a.toml");
  return std::string((std::istreambuf_iterator<char>(src)), std::istreambuf_iterator<char>());
}

// The error a machine file's text gives, or "<no error>".
std::string error_of(const std::string& t) {
  try {
    gm::parse_machine_toml(t, "t.toml");
  } catch (const gm::InputError& e) {
    return e.what();
  }
  return "<no error>";
}

gm::Motion line_motion(const AxisVec& a, const AxisVec& b) {
  gm::Motion m;
  m.kind = gm::MotionKind::Line;
  m.start_mm = a;
  m.end_mm = b;
  return m;
}

// The canonical motions of `program` on `machine`.
std::vector<gm::Motion> motions(const std::string& program, const gm::Machine& machine) {
  std::istringstream in(program);
  gm::InterpreterOptions o;
  o.machine = &machine;
  gm::ProgramStream stream(in, "t.nc", o);
  std::vector<gm::Motion> out;
  gm::Canon c;
  while (stream.next(c))
    if (const auto* m = std::get_if<gm::Motion>(&c)) out.push_back(*m);
  return out;
}

gm::Machine with_axes(const char* letters) {
  gm::Machine m = gm::default_machine();
  m.set_axes(*AxisLayout::of(letters), m.axes[0]);
  return m;
}

// Every record of a run of `program` on `m` (servo on, contour measured inline).
std::vector<gm::SampleRecord> records(const fs::path& program, const gm::Machine& m) {
  std::ifstream in(program);
  REQUIRE(in);
  gm::RunOptions o;
  o.config.machine = m;
  o.program_name = program.string();
  o.consumer_thread = false;
  gm::Run run(std::move(o), in, gm::InterpreterOptions{});
  std::vector<gm::SampleRecord> out;
  while (run.step() == gm::RunStatus::Working) out.push_back(run.last());
  return out;
}

}  // namespace

TEST_CASE("axis layouts: a subsequence of XYZABCUVW, each letter once") {
  const auto l = AxisLayout::of("XYZA");
  REQUIRE(l);
  CHECK(l->count == 4);
  CHECK(l->letters() == "XYZA");
  CHECK(l->program(3) == 3);
  CHECK_FALSE(l->is_xyz());
  CHECK(AxisLayout::of("xzc")->letters() == "XZC");
  CHECK(AxisLayout::of("xzc")->program(2) == 5);
  CHECK(AxisLayout::of("XYZABCUVW")->count == 9);
  CHECK(AxisLayout::of("XYZ")->is_xyz());
  CHECK_FALSE(AxisLayout::of(""));
  CHECK_FALSE(AxisLayout::of("XAZ"));    // out of order
  CHECK_FALSE(AxisLayout::of("XYZAA"));  // twice
  CHECK_FALSE(AxisLayout::of("XYQ"));    // not an axis
  CHECK(gm::axis_is_rotary(gm::axis_index('B')));
  CHECK_FALSE(gm::axis_is_rotary(gm::axis_index('U')));
}

TEST_CASE("feed length follows LinuxCNC: XYZ when they move, else UVW, else the rotary degrees") {
  // X3 Y4 with A90: the 5 mm XYZ path sets the time; A follows.
  CHECK(gm::motion_length_mm(line_motion(at({}), at({{'X', 3}, {'Y', 4}, {'A', 90}}))) == 5.0);
  // A and B alone: degrees, sqrt(30² + 40²).
  CHECK(gm::motion_length_mm(line_motion(at({{'A', 10}}), at({{'A', 40}, {'B', 40}}))) == 50.0);
  // U V with C: the UVW length.
  CHECK(gm::motion_length_mm(line_motion(at({}), at({{'U', 6}, {'V', 8}, {'C', 5}}))) == 10.0);
  // Part way along a mixed line every axis is in proportion.
  const gm::MotionGeometry g =
      gm::MotionGeometry::of(line_motion(at({}), at({{'X', 10}, {'A', 90}, {'W', -4}})));
  const AxisVec p = g.point_at(2.5);
  CHECK(p[0] == 2.5);
  CHECK(p[gm::axis_index('A')] == 22.5);
  CHECK(p[gm::axis_index('W')] == -1.0);
  // The contour is measured in X, Y and Z: a rotary axis away from the path does not count.
  double d = 0, sd = 0;
  g.distance(gm::Vec3(5, 0.25, 0), d, sd);
  CHECK(d == Approx(0.25));
}

TEST_CASE("rotary words are degrees in G20 too, and G93 times a mixed move by its XYZ length") {
  const gm::Machine m = with_axes("XYZA");
  const auto mv = motions("G20 G1 X1 A10 F10\nG93 G1 X0 A0 F2\nM2\n", m);
  REQUIRE(mv.size() == 2);
  CHECK(mv[0].end_mm[0] == Approx(25.4));
  CHECK(mv[0].end_mm[3] == 10.0);  // not 254
  // 25.4 mm of X in 1/2 minute: 50.8 mm/min, 30 s.
  CHECK(mv[1].feed_mm_min == Approx(50.8));
  CHECK(mv[1].inverse_time_s == Approx(30.0));
}

TEST_CASE("an axis word for an axis the machine lacks is a located error naming its axes") {
  const fs::path p = fs::temp_directory_path() / "gmotion-test-axes.nc";
  std::ofstream(p) << "G0 X1 A2\nG1 X2 B3 F100\nM2\n";
  auto r = gmtest::run_gmotion("check " + p.string() + " --axes XYZA");
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains(p.string() +
                                    ":2:7: error: axis B is not available: this machine has X, "
                                    "Y, Z and A"));
  CHECK_THAT(r.out, !Catch::Contains(":1:"));  // A is there
  r = gmtest::run_gmotion("check " + p.string());
  CHECK_THAT(r.out, Catch::Contains(p.string() +
                                    ":1:7: error: axis A is not available: this machine has X, Y "
                                    "and Z"));
  r = gmtest::run_gmotion("check " + p.string() + " --axes XAY");
  CHECK(r.code == 1);
  CHECK_THAT(r.out, Catch::Contains("--axes XAY: give axis letters in the order XYZABCUVW"));
  fs::remove(p);
}

TEST_CASE("machine file: axes.letters, a table per axis, written back the same") {
  const gm::Machine m =
      gm::load_machine_file(gm::test::kRepoRoot / "programs/machines/rotary-a.toml");
  CHECK(m.layout.letters() == "XYZA");
  REQUIRE(m.axes.size() == 4);
  CHECK(m.axes[3].rotary);
  CHECK(m.axes[3].v_max_mm_s == 360.0);  // v_max_deg_s
  CHECK(m.axes[3].mass_kg == 0.5);       // inertia_kg_m2
  CHECK(m.axes[3].f_max_N == 200.0);     // torque_max_Nm
  const gm::Machine back = gm::parse_machine_toml(gm::machine_to_toml(m), "back.toml");
  CHECK(back.layout.letters() == "XYZA");
  CHECK(back.axes[3].v_max_mm_s == 360.0);
  CHECK(gm::machine_to_toml(back) == gm::machine_to_toml(m));

  const std::string text = rotary_a_text();
  std::string no_a =
      text.substr(0, text.find("[axes.a]")) + text.substr(text.find("[work_offsets]"));
  CHECK_THAT(error_of(no_a), Catch::Contains("axes.a"));
  std::string bad = text;
  bad.replace(bad.find("\"XYZA\""), 6, "\"XYAZ\"");
  CHECK_THAT(error_of(bad),
             Catch::Contains("key 'axes.letters': must be axis letters in the order XYZABCUVW"));
}

TEST_CASE("rotary keys: degrees, torque and inertia, and wrapped_rotary on rotary axes only") {
  const std::string text = rotary_a_text();
  std::string wrapped = text;
  wrapped.insert(wrapped.find("damping_Nm_s_rad"), "wrapped_rotary = true\n");
  const gm::Machine w = gm::parse_machine_toml(wrapped, "w.toml");
  CHECK(w.axes[3].wrapped_rotary);
  CHECK(gm::machine_to_toml(w).find("wrapped_rotary = true") != std::string::npos);
  std::string both = text;
  both.insert(both.find("damping_Nm_s_rad"), "mass_kg = 3\n");
  CHECK_THAT(error_of(both), Catch::Contains("key 'axes.a.inertia_kg_m2': gives what "
                                             "'axes.a.mass_kg' gives: name one of them"));
  std::string on_x = text;
  on_x.insert(on_x.find("mass_kg = "), "wrapped_rotary = true\n");
  CHECK_THAT(error_of(on_x),
             Catch::Contains("key 'axes.x.wrapped_rotary': only a rotary axis (A, B, C) wraps"));
}

TEST_CASE("a rotary axis reports degrees, torque and power from its inertia, not a linear mass") {
  // A turns 3600 degrees at F36000 (600 deg/s, rotary-only: F in deg/min) on --axes XYZA: the
  // new A takes the rotary defaults (360 deg/s, 200 N m, 750 W, 0.5 kg m2, 1 N m s/rad).
  const fs::path d = fs::temp_directory_path() / "gmotion-test-rotary-units";
  fs::create_directories(d);
  { std::ofstream(d / "r.nc") << "G21 G90 G94\nG1 A3600 F36000\nM2\n"; }
  const auto r =
      gmtest::run_gmotion("run " + (d / "r.nc").string() +
                          " --axes XYZA --no-servo --summary-json " + (d / "r.json").string());
  CHECK(r.code == 0);
  CHECK(r.out.find("rotary  ferr max BLU (line)  v max deg/s (line)") != std::string::npos);
  CHECK(r.out.find("LIMIT A velocity deg/s: ") != std::string::npos);
  CHECK(r.out.find("torque") == std::string::npos);  // within 200 N m
  std::ifstream js(d / "r.json");
  const std::string j((std::istreambuf_iterator<char>(js)), std::istreambuf_iterator<char>());
  CHECK(j.find("\"a\":{\"following_err_max_blu\"") != std::string::npos);
  CHECK(j.find("\"velocity_max_deg_s\":{\"value\":600,") != std::string::npos);
  CHECK(j.find("\"x\":{\"following_err_max_blu\":{\"value\":0,\"line\":0},\"velocity_max_mm_s\"") !=
        std::string::npos);
  // The torque's worst sample lies between J·a_max and J·a_max + c·v_max (rad units), a_max
  // being the summary's own deg/s² peak.
  const auto number_after = [&](const std::string& key) {
    const std::size_t at = j.find(key, j.find("\"a\":{"));
    REQUIRE(at != std::string::npos);
    return std::stod(j.substr(at + key.size()));
  };
  const double k = 180.0 / 3.14159265358979323846;
  const double a_max = number_after("\"accel_max_deg_s2\":{\"value\":");
  const double torque =
      number_after("\"torque\":{\"limit\":200,\"violations\":0,\"worst\":{\"value\":");
  CHECK(torque >= 0.5 * a_max / k);
  CHECK(torque <= 0.5 * a_max / k + 1.0 * 600.0 / k);
  // At 600 deg/s the damping alone takes c·ω² = (600/k)² W.
  const double power =
      number_after("\"power\":{\"limit\":750,\"violations\":0,\"worst\":{\"value\":");
  CHECK(power >= (600.0 / k) * (600.0 / k));
  fs::remove_all(d);
}

TEST_CASE("an idle fourth axis leaves X, Y and Z sample for sample as on three axes") {
  const fs::path prog = gm::test::kRepoRoot / "programs" / "square.nc";
  const auto three = records(prog, gm::default_machine());
  const auto four = records(prog, with_axes("XYZA"));
  REQUIRE(three.size() == four.size());
  for (std::size_t k = 0; k < three.size(); ++k) {
    INFO("sample " << k);
    REQUIRE(three[k].ref_blu.head<3>() == four[k].ref_blu.head<3>());
    REQUIRE(three[k].enc_blu.head<3>() == four[k].enc_blu.head<3>());
    REQUIRE(three[k].contour_err_blu == four[k].contour_err_blu);
    REQUIRE(four[k].enc_blu[3] == 0);
  }
}

TEST_CASE("nine axes: each ends exactly on its programmed end, rotary in its own BLU") {
  gm::Machine m = with_axes("XYZABCUVW");
  m.axes[3].blu_mm = 0.01;  // A: 0.01 degree per count
  const auto recs = records(gm::test::kRepoRoot / "tests/golden/programs/nine-axis.nc", m);
  REQUIRE(!recs.empty());
  const auto mv = motions("G0 X1.5 Y2 Z3 A45.67 B-30 C720 U4 V-5 W6\nM2\n",
                          m);  // the same machine, a direct check
  REQUIRE(mv.size() == 1);
  CHECK(mv[0].end_mm[5] == 720.0);
  // The program returns every axis to 0 but Z (to 5 mm); on the way A reached 180 degrees =
  // 18000 counts at the end of the arc, passed within one sample (at most 0.38 degrees: 60
  // degrees over the 15.7 mm arc at 25 mm/s), since time carries across continuous blocks.
  const gm::SampleRecord& last = recs.back();
  for (int a = 0; a < 9; ++a) {
    INFO("axis " << m.layout.letter(a));
    const std::int64_t end = a == 2 ? 5000 : 0;
    CHECK(last.ref_blu[a] == end);
    CHECK(std::llabs(last.enc_blu[a] - end) <= 1);
  }
  std::int64_t a_max = 0;
  for (const auto& r : recs) a_max = std::max(a_max, r.cmd_blu[3]);
  CHECK(a_max <= 18000);
  CHECK(a_max >= 18000 - 39);
}

TEST_CASE("an axis past X, Y, Z may have its own Acc/Dec: A's output is its own moving average") {
  // X keeps the machine's Blackman filter (41 taps); A gets a linear profile of τ = 0.2 s, 50
  // equal taps, so A's Acc/Dec output is the mean of its last 50 commands, rounded half away
  // from zero (the exact integer FIR), computed here from the trace's own a_cmd column.
  gm::Machine m = with_axes("XYZA");
  m.axes[3].accdec_profile = "linear";
  m.axes[3].accdec_tau_s = 0.2;
  std::istringstream in("G21 G90 G64\nG1 X10 A90 F1200\nG0 X0 A0\nM2\n");
  gm::RunOptions o;
  o.config.machine = m;
  o.config.servo = false;
  o.program_name = "own-accdec.nc";
  o.consumer_thread = false;
  gm::Run run(std::move(o), in, gm::InterpreterOptions{});
  std::vector<gm::SampleRecord> recs;
  while (run.step() == gm::RunStatus::Working) recs.push_back(run.last());
  REQUIRE(recs.size() > 100);
  std::int64_t worst = 0, x_differs = 0;
  for (std::size_t k = 0; k < recs.size(); ++k) {
    std::int64_t sum = 0;
    for (std::size_t i = 0; i < 50; ++i) sum += k >= i ? recs[k - i].cmd_blu[3] : 0;
    const std::int64_t mean = sum >= 0 ? (2 * sum + 50) / 100 : -((-2 * sum + 50) / 100);
    worst = std::max<std::int64_t>(worst, std::llabs(recs[k].ref_blu[3] - mean));
    std::int64_t xs = 0;  // X through a 50-tap average would differ from its Blackman output
    for (std::size_t i = 0; i < 50; ++i) xs += k >= i ? recs[k - i].cmd_blu[0] : 0;
    x_differs += recs[k].ref_blu[0] != (xs >= 0 ? (2 * xs + 50) / 100 : -((-2 * xs + 50) / 100));
  }
  CHECK(worst == 0);
  CHECK(x_differs > 50);
  CHECK(recs.back().ref_blu[0] == 0);  // both end exactly
  CHECK(recs.back().ref_blu[3] == 0);

  // The machine file: [axes.a.accdec] is read and written back; X, Y and Z may not have one.
  const gm::Machine f = gm::parse_machine_toml(gm::machine_to_toml(m), "own.toml");
  CHECK(f.axes[3].accdec_profile == "linear");
  CHECK(f.axes[3].accdec_tau_s == 0.2);
  CHECK(f.axes[0].accdec_profile.empty());
  std::string text = gm::machine_to_toml(m);
  text.insert(text.find("[axes.y]"), "[axes.x.accdec]\ntau_s = 0.1\n\n");
  try {
    gm::parse_machine_toml(text, "bad.toml");
    FAIL("no error for [axes.x.accdec]");
  } catch (const gm::InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("key 'axes.x.accdec': X, Y and Z share the machine's"));
  }
}
