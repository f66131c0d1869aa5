// Checking every error in one pass, the canonical kinds of G33.1 and G38.x in `gmotion moves`,
// G74/G84 in G18 and G19, and [RS274NGC]DISABLE_FANUC_STYLE_SUB.
#include "gcode_helpers.hpp"
#include "support/run_command.hpp"
#include "support/scratch_dir.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace gmtest;

namespace {

// An unresolved call on line 3, bad words on lines 7 and 12.
const char* const kThreeErrors =
    "(three errors, one pass)\n"
    "G21 G90 G94 F100\n"
    "o<missing> call\n"
    "G1 X1\n"
    "G1 Y1\n"
    "G1 X2\n"
    "G1 X3 Y&\n"
    "G1 Y2\n"
    "G1 X4\n"
    "G1 Y3\n"
    "G1 X5\n"
    "G1 X6 !7\n"
    "M2\n";

std::vector<gm::Diagnostic> check_all(const std::string& program, gm::CheckThreads threads,
                                      const gm::InterpreterOptions& opts = {}) {
  std::istringstream in(program);
  std::vector<gm::Diagnostic> d;
  gm::check_program_diagnostics(in, "t.ngc", opts, d, threads);
  return d;
}

std::vector<int> error_lines(const std::vector<gm::Diagnostic>& d) {
  std::vector<int> out;
  for (const auto& x : d)
    if (x.severity == gm::Severity::Error) out.push_back(x.loc.line);
  return out;
}

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = (scratch_dir("check-all") / name).string();
  std::ofstream(path) << text;
  return path;
}

}  // namespace

TEST_CASE("check reports every error in one pass: on after a call it cannot resolve") {
  for (const auto threads : {gm::CheckThreads::Auto, gm::CheckThreads::Single}) {
    const auto d = check_all(kThreeErrors, threads);
    REQUIRE(error_lines(d) == std::vector<int>{3, 7, 12});
    CHECK(d[0].code == code(gm::ErrorCode::UndefinedSubroutine));
    CHECK(d[0].message.find("o<missing>") != std::string::npos);
    for (const auto& x : d) CHECK(x.severity == gm::Severity::Error);
  }
  // Two unresolved calls, an M98 among them: each reported where it is, the rest read on.
  const auto d = check_all("G0 X1\no<a> call\nM98 P12\nG1 X2 Y&\nM2\n", gm::CheckThreads::Single);
  CHECK(error_lines(d) == std::vector<int>{2, 3, 4});
  // A subroutine defined further down is still found (the check reads on only after a miss).
  CHECK(error_lines(check_all("o<s> call\nG0 X1\nM2\no<s> sub\nG0 Y1\no<s> endsub\n",
                              gm::CheckThreads::Single))
            .empty());
}

TEST_CASE("check stops at control flow it cannot follow, and says so") {
  const auto d = check_all("G0 X1\no1 endwhile\nG1 X2 Y&\nM2\n", gm::CheckThreads::Single);
  REQUIRE(d.size() == 2);
  CHECK(d[0].severity == gm::Severity::Error);
  CHECK(d[0].loc.line == 2);
  CHECK(d[1].severity == gm::Severity::Note);
  CHECK(d[1].loc.line == 2);
  CHECK(d[1].message.rfind("checking stopped here", 0) == 0);
}

TEST_CASE("gmotion check prints all three errors, located, and run and moves still refuse") {
  const std::string path = write_temp("check-all-three.ngc", kThreeErrors);
  auto r = run_gmotion("check " + path);
  CHECK(r.code == 1);
  CHECK(r.out.find("check-all-three.ngc:3:1: error:") != std::string::npos);
  CHECK(r.out.find("check-all-three.ngc:7:") != std::string::npos);
  CHECK(r.out.find("check-all-three.ngc:12:") != std::string::npos);
  CHECK(r.out.find(": 3 errors") != std::string::npos);
  r = run_gmotion("run " + path);
  CHECK(r.code == 1);
  CHECK(r.out.find("check-all-three.ngc:12:") != std::string::npos);
  r = sh(gmotion_bin() + " moves " + path + " 2>/dev/null");
  CHECK(r.code == 1);
  CHECK(r.out.empty());
}

TEST_CASE("gmotion moves names G33.1 rigid_tap and G38.x probe moves (RIGID_TAP, STRAIGHT_PROBE)") {
  const auto r = sh("printf 'G21 G90 F100 S600 M3\\nG33.1 Z-3 K1\\nG38.3 X5\\nG1 Y1\\nM2\\n' | " +
                    gmotion_bin() + " moves -");
  CHECK(r.code == 0);
  CHECK(r.out ==
        "{\"line\":2,\"kind\":\"rigid_tap\",\"end\":[0,0,-3],\"feed\":600,\"mm_per_rev\":1}\n"
        "{\"line\":2,\"kind\":\"rigid_tap\",\"end\":[0,0,0],\"feed\":600,\"mm_per_rev\":1}\n"
        "{\"line\":3,\"kind\":\"probe\",\"end\":[5,0,0],\"feed\":100}\n"
        "{\"line\":3,\"kind\":\"probe\",\"end\":[4.746,0,0],\"feed\":100}\n"
        "{\"line\":4,\"kind\":\"line\",\"end\":[4.746,1,0],\"feed\":100}\n");
  // The pipeline moves them as lines.
  const auto m = motions("G21 G90 F100 S600 M3\nG33.1 Z-3 K1\nG38.2 X5\nM2\n");
  REQUIRE(m.size() == 4);
  for (const auto& x : m) CHECK(x.kind == gm::MotionKind::Line);
  CHECK(m[0].canon == gm::LineCanon::RigidTap);
  CHECK(m[3].canon == gm::LineCanon::Probe);
}

// LinuxCNC 2.9's convert_cycle_g74_g84 hands the plane's coordinates to cycle_feed in the wrong
// order in G18 and G19, so rs274 feeds diagonally (docs/machine-codes.md); gmotion taps along the
// cycle axis, as in G17 and as every other cycle does.
TEST_CASE("G84 and G74 in G18 and G19 tap along the cycle axis (rs274 does not)") {
  const auto g19 = motions("G21 G90 G94 F100 S500 M3\nG0 X1 Y2 Z3\nG19 G98 G84 Y5 Z6 X-4 R8\nM2\n");
  REQUIRE(g19.size() == 5);  // to the start; up to R, over the hole, in, out (to R: G98 below R)
  CHECK(g19[3].start_mm.head<3>() == Eigen::Vector3d(8, 5, 6));
  CHECK(g19[3].end_mm.head<3>() == Eigen::Vector3d(-4, 5, 6));  // rs274: (6, -4, 5)
  CHECK(g19[4].end_mm.head<3>() == Eigen::Vector3d(8, 5, 6));
  const auto g18 = motions("G21 G90 G94 F100 S500 M4\nG0 X1 Y2 Z3\nG18 G98 G74 Z5 X6 Y-4 R8\nM2\n");
  REQUIRE(g18.size() == 5);
  CHECK(g18[3].start_mm.head<3>() == Eigen::Vector3d(6, 8, 5));
  CHECK(g18[3].end_mm.head<3>() == Eigen::Vector3d(6, -4, 5));  // rs274: (-4, 5, 6)
  CHECK(g18[4].end_mm.head<3>() == Eigen::Vector3d(6, 8, 5));
}

TEST_CASE("DISABLE_FANUC_STYLE_SUB: M98, M99 in a subprogram and a bare O-word are errors") {
  gm::Machine m;
  gm::InterpreterOptions opts{&m, false};
  opts.fanuc_subs_disabled = true;
  const std::string program = "G0 X1\nM98 P100\nG0 X2\nM2\nO100\nG1 X3 F100\nM99\n";
  const auto d = check_all(program, gm::CheckThreads::Single, opts);
  REQUIRE(error_lines(d) == std::vector<int>{2});
  CHECK(d[0].code == code(gm::ErrorCode::SubprogramMisused));
  CHECK(d[0].message.find("DISABLE_FANUC_STYLE_SUB") != std::string::npos);
  // A bare O-word is refused even where the program passes over it; M99 in the main program
  // still ends it.
  CHECK(error_lines(check_all("o<s> sub\nO100\no<s> endsub\nG0 X1\nM99\n", gm::CheckThreads::Single,
                              opts)) == std::vector<int>{2});
  // Allowed by default.
  CHECK(error_lines(check_all(program, gm::CheckThreads::Single, {&m, false})).empty());
}
