// --dialect haas through the CLI: each test names the Haas document and section it follows
// (read through the search tool); the expected moves are worked by hand.
#include <catch2/catch.hpp>

#include "cli_moves.hpp"
#include "interp/program.hpp"

#include <sstream>
#include <variant>

#include <string>

namespace {
using gmtest::check_points;
using gmtest::cli_moves;
using gmtest::CliMoves;
using gmtest::Point3;

std::string haas_program(const std::string& name, const std::string& text) {
  return gmtest::scratch_program("haas", name, text);
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
  return n;
}
}  // namespace

TEST_CASE(
    "haas: M97 P1000 L5, the manual's local subprogram (96-8000, M97 Local Sub-Program "
    "Call)") {
  // Haas mill operator's manual 96-8000, "M97 Local Sub-Program Call": P names a line number N
  // in the same program, the subroutine ends with M99, L repeats it; the manual's example with
  // its tool change left out. Each pass: Z down 0.1, X2, Z down 0.1, X0.
  const std::string file = haas_program("m97.nc",
                                        "%\n"
                                        "O00011 (M97 CALL)\n"
                                        "G00 G90 G54 X0 Y0 Z1.\n"
                                        "G01 Z0 F20.\n"
                                        "M97 P1000 L5 (L5 RUNS THE N1000 LINES FIVE TIMES)\n"
                                        "G00 G90 Z1.\n"
                                        "M30\n"
                                        "N1000 (THE LOCAL SUBPROGRAM)\n"
                                        "G01 G91 Z-0.1\n"
                                        "G90 X2.\n"
                                        "G91 Z-0.1\n"
                                        "G90 X0\n"
                                        "M99\n"
                                        "%\n");
  const CliMoves m = cli_moves(file, "--dialect haas");
  CHECK(m.code == 0);
  std::vector<Point3> want{{0, 0, 1}, {0, 0, 0}};
  for (int k = 0; k < 5; ++k) {
    const double z = -0.2 * k;
    want.push_back({0, 0, z - 0.1});
    want.push_back({2, 0, z - 0.1});
    want.push_back({2, 0, z - 0.2});
    want.push_back({0, 0, z - 0.2});
  }
  want.push_back({0, 0, 1});
  check_points(m, m.ends, want);
  // Without L: one pass; the same program under fanuc refuses M97.
  const std::string once = haas_program("m97_once.nc",
                                        "G0 X0 Y0 Z1.\nM97 P20\nG0 Z5.\nM30\n"
                                        "N20 G1 X3. F100.\nM99\n");
  check_points(cli_moves(once, "--dialect haas"), cli_moves(once, "--dialect haas").ends,
               {{0, 0, 1}, {3, 0, 1}, {3, 0, 5}});
  const CliMoves fanuc = cli_moves(once, "--dialect fanuc");
  CHECK(fanuc.code == 1);
  CHECK(fanuc.out.find("M97 (Haas local subprogram call") != std::string::npos);
}

TEST_CASE("haas: M97 to a missing N is a located error naming N") {
  const std::string file =
      haas_program("m97_missing.nc", "G0 X1.\nM97 P2000\nM30\nN200 G0 X2.\nM99\n");
  const auto r = gmtest::sh(gmtest::gmotion_bin() + " check " + file + " --dialect haas 2>&1");
  CHECK(r.code == 1);
  CHECK(r.out.find("m97_missing.nc:2:1: error: M97 P2000: no block N2000 in this program") !=
        std::string::npos);
  const std::string words = haas_program("m97_words.nc", "M97 P10 X1.\nM30\nN10 M99\n");
  const auto w = gmtest::sh(gmtest::gmotion_bin() + " check " + words + " --dialect haas 2>&1");
  CHECK(w.code == 1);
  CHECK(w.out.find("M97 takes P (the sequence number) and L (repeats) only, not X") !=
        std::string::npos);
}

TEST_CASE("haas: G154 P1-P99 work offsets set by G10 L20 (haas.co.uk, Programmable Offsets)") {
  // Haas's G10 page: "L20 Auxiliary work coordinate origin", "P1-P99 G154 P1-P99 reference
  // auxiliary coordinate (L20)"; its example "G10 L20 P2 G90 X100. Y80." sets the origin from
  // the home position, "G10 L2 P1 G91 X60." moves one.
  const std::string file = haas_program("g154.nc",
                                        "G21 G90\n"
                                        "G10 L20 P12 X100. Y50. Z-10.\n"
                                        "G154 P12\n"
                                        "G0 X1. Y2. Z3.\n"
                                        "G10 L20 P12 G91 X10.\n"
                                        "G90 X1.\n"
                                        "G54 X0 Y0 Z0\n"
                                        "G154 P12 X0\n"
                                        "M30\n");
  const CliMoves m = cli_moves(file, "--dialect haas");
  CHECK(m.code == 0);
  // G154 P12: origin (100, 50, -10); moved +10 in X while in effect; G54 is the machine zero;
  // G154 P12 again: X0 is 110.
  check_points(m, m.ends, {{101, 52, -7}, {111, 52, -7}, {0, 0, 0}, {110, 0, 0}});
  const std::string bad = haas_program("g154_bad.nc", "G154 P100\nM30\n");
  const auto r = gmtest::sh(gmtest::gmotion_bin() + " check " + bad + " --dialect haas 2>&1");
  CHECK(r.code == 1);
  CHECK(r.out.find("G154 P100: the work offset is P1-P99") != std::string::npos);
  // LinuxCNC has no G154.
  CHECK(gmtest::sh(gmtest::gmotion_bin() + " check " + file + " 2>&1").code == 1);
}

TEST_CASE(
    "haas: G187 E is the path tolerance, G103 and machine M codes passed over, M41/M42 "
    "recorded (haas.co.uk Smooth Operator, 96-8000 M codes)") {
  // haas.co.uk "Smooth Operator": G187 P1/P2/P3 = rough/medium/finish (Setting 191); E is the
  // corner accuracy: G64 P. 96-8000 M CODES: M41 low gear, M42 high gear override (no motion).
  const std::string file = haas_program("g187.nc",
                                        "G21 G90\n"
                                        "G187 P2 E0.05\n"
                                        "G103 P1\n"
                                        "M31\nM88\nM31\nM51\nM58\n"
                                        "M41\nS500 M3\nM42\n"
                                        "M19 P90.\n"
                                        "G0 X1.\n"
                                        "G187 P1\n"
                                        "G1 X2. F100.\n"
                                        "M33\nM89\nM30\n");
  const CliMoves m = cli_moves(file, "--dialect haas --io");
  CHECK(m.code == 0);
  CHECK(count(m.out, "warning: G187 P2 (smoothness) is not modelled") == 1);
  CHECK(count(m.out, "G187 P1") == 0);  // warned once
  CHECK(count(m.out, "warning: G103 (block look-ahead limit) is passed over") == 1);
  for (const char* code : {"M31", "M88", "M51", "M58", "M33", "M89"})
    CHECK(count(m.out, std::string(code) + " is a machine function LinuxCNC does not have") == 1);
  CHECK(m.out.find("\"kind\":\"user_mcode\",\"code\":41") != std::string::npos);
  CHECK(m.out.find("\"kind\":\"user_mcode\",\"code\":42") != std::string::npos);
  CHECK(m.out.find("\"kind\":\"spindle_orient\",\"angle\":90") != std::string::npos);
}

TEST_CASE("haas: G187 E is LinuxCNC's G64 P path tolerance (haas.co.uk, Smooth Operator)") {
  gm::Machine machine;
  gm::InterpreterOptions opts{&machine, false};
  opts.dialect = gm::Dialect::Haas;
  std::istringstream in("G21 G90\nG187 P2 E0.05\nG1 X1. F100.\nG187 E0.2\nX2.\nG187\nX3.\nM30\n");
  gm::ProgramStream s(in, "g187.nc", opts);
  std::vector<gm::Motion> moves;
  gm::Canon c;
  while (s.next(c))
    if (const auto* m = std::get_if<gm::Motion>(&c)) moves.push_back(*m);
  REQUIRE(moves.size() == 3);
  CHECK(moves[0].path_mode == gm::PathMode::Continuous);
  CHECK(moves[0].path_tolerance_mm == 0.05);
  CHECK(moves[1].path_tolerance_mm == 0.2);
  // G187 alone: G64 without P, the machine's tolerance
  CHECK(moves[2].path_tolerance_mm == machine.path_tolerance_mm);
}

TEST_CASE("haas: a tool missing from the table is a zero-length tool with one warning") {
  // The default machine's table has tools 1-4 (machine/tool_table.cpp); tool 20 is missing.
  const std::string file = haas_program("tool20.nc",
                                        "G21 G90\nT20 M06\nG0 G43 H20 Z10.\nG0 X5.\n"
                                        "G41 D20 G1 X10. F100.\nG40 G0 X20.\nM30\n");
  for (const char* dialect : {"haas", "fanuc", "mach3", "grbl"}) {
    INFO(dialect);
    if (std::string(dialect) == "grbl") continue;  // grbl has no G43 H or G41 D
    const CliMoves m = cli_moves(file, std::string("--dialect ") + dialect);
    CHECK(m.code == 0);
    CHECK(count(m.out, "warning: tool 20 is not in the tool table") == 1);
    // length 0: Z10 is Z10; diameter 0: the compensated line ends on the programmed point
    check_points(m, m.ends, {{0, 0, 10}, {5, 0, 10}, {10, 0, 10}, {20, 0, 10}});
  }
  const std::string grbl = haas_program("tool20_grbl.nc", "T20\nG0 X1\nM2\n");
  const CliMoves g = cli_moves(grbl, "--dialect grbl");
  CHECK(g.code == 0);
  CHECK(count(g.out, "warning: tool 20 is not in the tool table") == 1);
  // LinuxCNC: its error, as rs274's "Requested tool 20 not found in the tool table".
  const CliMoves l = cli_moves(file, "");
  CHECK(l.code == 1);
  CHECK(l.out.find("tool 20 is not in the tool table") != std::string::npos);
}

TEST_CASE(
    "haas: the bundled flange program (G154 P12, M97 P1000 L3, G68 R45., G16 bolt "
    "circle), moves worked by hand") {
  // Work offset G154 P12 = (100, 50, 0); tool 3 is 45 long, tool 2 60 (the default table); so
  // machine = work + (100, 50, 0) + (0, 0, length).
  const std::string file = std::string(GMOTION_TESTS_DIR) + "/../programs/dialects/haas_flange.nc";
  const CliMoves m = cli_moves(file, "--dialect haas");
  CHECK(m.code == 0);
  const auto at = [](double x, double y, double z, double length) {
    return Point3{100 + x, 50 + y, z + length};
  };
  std::vector<Point3> want{{80, 30, 0}, at(-20, -20, 5, 45), at(-20, -20, 0, 45)};
  for (int pass = 1; pass <= 3; ++pass) {  // M97 P1000 L3: the square, 2 mm deeper each time
    const double z = -2.0 * pass;
    for (const auto& xy :
         {std::array<double, 2>{-20, -20}, {20, -20}, {20, 20}, {-20, 20}, {-20, -20}})
      want.push_back(at(xy[0], xy[1], z, 45));
  }
  const double s = 15.0 * std::sqrt(0.5);  // G68 R45.: X-15. Y0 -> (-s, -s), X15. -> (s, s)
  want.push_back(at(-20, -20, 5, 45));
  want.push_back(at(-s, -s, 5, 45));
  want.push_back(at(-s, -s, -2, 45));
  want.push_back(at(s, s, -2, 45));
  want.push_back(at(s, s, 5, 45));
  want.push_back(at(s, s, 25, 60));
  const double h = 30.0 * std::sqrt(0.5);  // G16: R30 at 45, 135, 225, 315 degrees
  for (const auto& xy : {std::array<double, 2>{h, h}, {-h, h}, {-h, -h}, {h, -h}}) {
    want.push_back(at(xy[0], xy[1], 25, 60));  // G98: from and back to the initial Z25
    want.push_back(at(xy[0], xy[1], 2, 60));
    want.push_back(at(xy[0], xy[1], -8, 60));
    want.push_back(at(xy[0], xy[1], 25, 60));
  }
  want.push_back({100 + h, 50 - h, 0});  // G91 G28 Z0.: machine Z0
  check_points(m, m.ends, want);
  CHECK(count(m.out, "warning") == 2);                  // G187 P2, M31
  CHECK(cli_moves(file, "--dialect fanuc").code == 1);  // M97, G154: Haas's
}
