// Fanuc's modal rules under --dialect fanuc and haas through the CLI: each test names the manual
// and section it follows (read through the search tool); the expected moves are worked by hand.
#include <catch2/catch.hpp>

#include "cli_moves.hpp"

#include <cmath>
#include <string>

namespace {
using gmtest::check_points;
using gmtest::cli_moves;
using gmtest::CliMoves;
using gmtest::Point3;

std::string modal_program(const std::string& name, const std::string& text) {
  return gmtest::scratch_program("fanuc-modal", name, text);
}
}  // namespace

TEST_CASE("fanuc-modal: axis words after G80 move in the group 01 mode (96-8000 canned cycles)") {
  // Haas 96-8000 "CANNED CYCLES": a cycle, once selected, runs at every X/Y motion until G80
  // cancels it; G00-G03 (group 01) are not changed by it, so after G80 (or with it) the axis
  // words move in the G0/G1 mode programmed before the cycle. LinuxCNC refuses them.
  const std::string file = modal_program("g80.nc",
                                         "G21 G90 G17 G98\n"
                                         "G0 X0 Y0 Z10.\n"
                                         "G1 F100.\n"
                                         "G81 X10. Y0 Z-5. R2.\n"
                                         "G80\n"
                                         "X30. Y5.\n"
                                         "G0 Z20.\n"
                                         "G81 X40. Y0 Z-5. R2.\n"
                                         "G80 X50.\n"
                                         "M30\n");
  for (const char* dialect : {"fanuc", "haas"}) {
    INFO(dialect);
    const CliMoves m = cli_moves(file, std::string("--dialect ") + dialect);
    CHECK(m.code == 0);
    check_points(m, m.ends,
                 {{0, 0, 10},
                  {10, 0, 10},
                  {10, 0, 2},
                  {10, 0, -5},
                  {10, 0, 10},
                  {30, 5, 10},  // G1: the mode before the cycle
                  {30, 5, 20},
                  {40, 0, 20},
                  {40, 0, 2},
                  {40, 0, -5},
                  {40, 0, 20},
                  {50, 0, 20}});  // G80 X50.: G0, the mode in force
    REQUIRE(m.kinds.size() == 12);
    CHECK(m.kinds[5] == "line");
    CHECK(m.kinds[11] == "rapid");
  }
  CHECK(cli_moves(file, "").code == 1);
}

TEST_CASE("fanuc-modal: G91 G28 Z0 returns through an incremental intermediate point") {
  // G28 goes to the intermediate point (incremental under G91: Z0 is where the tool is, Z5. is
  // 5 above), then to the home position (machine 0 on the axes named).
  const std::string file = modal_program("g28.nc",
                                         "G21 G90\nG0 X10. Y20. Z30.\nG91 G28 Z0.\nG90\n"
                                         "G0 Z30.\nG91 G28 Z5.\nG90\nM30\n");
  for (const char* dialect : {"fanuc", "haas", "linuxcnc"}) {
    INFO(dialect);
    const CliMoves m = cli_moves(file, std::string("--dialect ") + dialect);
    CHECK(m.code == 0);
    check_points(m, m.ends, {{10, 20, 30}, {10, 20, 0}, {10, 20, 30}, {10, 20, 35}, {10, 20, 0}});
  }
}

TEST_CASE(
    "fanuc-modal: G16 polar bolt circle (Fanuc 16/18-MC operator's manual, 9.2 polar "
    "coordinate command)") {
  // 9.2: under G16 the first axis of the plane is the radius, the second the angle
  // (counterclockwise from the first axis); G90 measures from the work zero. Three holes on
  // R100 at 30, 150 and 270 degrees.
  const std::string file = modal_program("g16.nc",
                                         "G21 G17 G90\n"
                                         "G0 X0 Y0 Z10.\n"
                                         "G16\n"
                                         "G98 G81 X100. Y30. Z-20. R-5. F200.\n"
                                         "Y150.\n"
                                         "Y270.\n"
                                         "G15 G80\n"
                                         "G0 X0 Y0\n"
                                         "M30\n");
  const double c = 100.0 * std::sqrt(3.0) / 2.0;
  std::vector<Point3> want{{0, 0, 10}};
  for (const Point3& h : {Point3{c, 50, 0}, Point3{-c, 50, 0}, Point3{0, -100, 0}}) {
    want.push_back({h[0], h[1], 10});
    want.push_back({h[0], h[1], -5});
    want.push_back({h[0], h[1], -20});
    want.push_back({h[0], h[1], 10});
  }
  want.push_back({0, 0, 10});
  const CliMoves m = cli_moves(file, "--dialect haas");
  CHECK(m.code == 0);
  check_points(m, m.ends, want);
  // G91: the angle is added to the angle so far (the radius kept about the work zero); G91
  // with a radius measures it from the current point.
  const std::string inc = modal_program("g16_inc.nc",
                                        "G21 G17 G90 G16\n"
                                        "G1 X50. Y0 F100.\n"
                                        "G91 Y90.\n"
                                        "Y90.\n"
                                        "X10. Y-90.\n"
                                        "G90 G15\n"
                                        "G1 X0 Y0\n"
                                        "M30\n");
  const CliMoves mi = cli_moves(inc, "--dialect fanuc");
  CHECK(mi.code == 0);
  // 0 -> 90 -> 180 degrees on R50; then 10 from (-50, 0) at 180 - 90 = 90 degrees
  check_points(mi, mi.ends, {{50, 0, 0}, {0, 50, 0}, {-50, 0, 0}, {-50, 10, 0}, {0, 0, 0}});
  CHECK(cli_moves(file, "").code == 1);  // LinuxCNC has no G16 (its polar words are @ ^)
}

TEST_CASE(
    "fanuc-modal: G68 R45. coordinate rotation (Haas mill operator's manual, G68 "
    "Rotation)") {
  // The Haas page: G68 rotates the X Y (G17) values after it about the centre given, or the
  // current location when none is; R is the angle, counterclockwise positive; values on the
  // G68 line itself are not rotated.
  const double h = std::sqrt(0.5) * 10.0;
  const std::string file = modal_program("g68.nc",
                                         "G21 G17 G90\n"
                                         "G0 X0 Y0 Z0\n"
                                         "G68 X0 Y0 R45.\n"
                                         "G1 X10. Y0 F100.\n"
                                         "G91 Y10.\n"
                                         "G90 G69\n"
                                         "G1 X10. Y10.\n"
                                         "G68 R90.\n"
                                         "G1 X20. Y10.\n"
                                         "G3 X10. Y20. I-10. J0\n"
                                         "G69\n"
                                         "G0 X0 Y0\n"
                                         "M30\n");
  const CliMoves m = cli_moves(file, "--dialect haas");
  CHECK(m.code == 0);
  // about (0, 0): (10, 0) -> (h, h); G91 Y10 turned -> (0, 2h); about (10, 10), the tool's
  // point: (20, 10) -> (10, 20); the arc (20, 10) -> (10, 20) about (10, 10) -> (10, 20) ->
  // (0, 10) about (10, 10), still counterclockwise
  check_points(m, m.ends,
               {{h, h, 0}, {0, 2 * h, 0}, {10, 10, 0}, {10, 20, 0}, {0, 10, 0}, {0, 0, 0}});
  REQUIRE(m.kinds.size() == 6);
  CHECK(m.kinds[4] == "arc");
  CHECK(std::abs(m.centres[4][0] - 10.0) < 1e-9);
  CHECK(std::abs(m.centres[4][1] - 10.0) < 1e-9);
  CHECK(m.out.find("\"dir\":\"ccw\"") != std::string::npos);
  const std::string no_r = modal_program("g68_no_r.nc", "G68 X0 Y0\nM30\n");
  const CliMoves e = cli_moves(no_r, "--dialect fanuc");
  CHECK(e.code == 1);
  CHECK(e.out.find("G68 needs R") != std::string::npos);
}

TEST_CASE("fanuc-modal: G51 P2. scaling, G50 cancel (96-8000, G51 Scaling)") {
  // 96-8000 "G51 Scaling": X Y Z the centre (the last commanded position when not given), P
  // the factor for all axes; X, Y, Z, I, J, K and R values are multiplied about the centre.
  const std::string file = modal_program("g51.nc",
                                         "G21 G90 G17\n"
                                         "G0 X0 Y0 Z0\n"
                                         "G51 X10. Y10. P2.\n"
                                         "G1 X20. Y10. F100.\n"
                                         "G2 X30. Y0 R10.\n"
                                         "G1 Z-1.\n"
                                         "G50\n"
                                         "G1 X0 Y0\n"
                                         "M30\n");
  const CliMoves m = cli_moves(file, "--dialect fanuc");
  CHECK(m.code == 0);
  // (20, 10) -> (30, 10); the R10 arc (20,10) -> (30,0) about (20,0) -> R20 (30,10) -> (50,-10)
  // about (30,-10); Z-1 about Z0 (the point when G51 was read) -> -2; after G50 the tool is
  // where it is (Z-2)
  check_points(m, m.ends, {{30, 10, 0}, {50, -10, 0}, {50, -10, -2}, {0, 0, -2}});
  check_points(m, m.centres, {{0, 0, 0}, {30, -10, 0}, {0, 0, 0}, {0, 0, 0}});
  // per-axis factors (I J K) and a negative one (a mirror image)
  const std::string ijk = modal_program("g51_ijk.nc",
                                        "G21 G90\nG51 X0 Y0 Z0 I3. J-2. K1.\n"
                                        "G1 X1. Y1. F100.\nG50\nM30\n");
  const CliMoves mi = cli_moves(ijk, "--dialect fanuc");
  check_points(mi, mi.ends, {{3, -2, 0}});
  CHECK(cli_moves(file, "").code == 1);
}

TEST_CASE("fanuc-modal: G51.1 mirror image turns arcs the other way (ISO milling: G51.1)") {
  // SINUMERIK ISO milling (programmable mirror image, G51.1/G50.1): mirrored in one axis of the
  // plane, G02 and G03 are interchanged (and G41/G42).
  const std::string file = modal_program("g511.nc",
                                         "G21 G90 G17\n"
                                         "G0 X0 Y0 Z0\n"
                                         "G51.1 X0\n"
                                         "G1 X10. Y5. F100.\n"
                                         "G2 X20. Y-5. I0 J-10.\n"
                                         "G50.1 X0\n"
                                         "G1 X0 Y0\n"
                                         "M30\n");
  const CliMoves m = cli_moves(file, "--dialect fanuc");
  CHECK(m.code == 0);
  check_points(m, m.ends, {{-10, 5, 0}, {-20, -5, 0}, {0, 0, 0}});
  check_points(m, m.centres, {{0, 0, 0}, {-10, -5, 0}, {0, 0, 0}});
  CHECK(m.out.find("\"dir\":\"ccw\"") != std::string::npos);
  REQUIRE(m.kinds.size() == 3);
  CHECK(m.kinds[2] == "line");
}

TEST_CASE("fanuc-modal: G41 D again with compensation on changes the tool (LinuxCNC refuses)") {
  // Tool 1 is 6 mm (radius 3), tool 2 is 3 mm (radius 1.5) in the default table. From the
  // second G41 on the compensation starts again: the next move is an entry move from where the
  // tool is to 1.5 left of the programmed end.
  const std::string file = modal_program("g41.nc",
                                         "G21 G90 G17\n"
                                         "G0 X0 Y-20. Z0\n"
                                         "G41 D1 G1 X0 Y0 F100.\n"
                                         "G1 X50.\n"
                                         "G41 D2\n"
                                         "G1 X100.\n"
                                         "G40 G1 X100. Y-20.\n"
                                         "M30\n");
  const CliMoves m = cli_moves(file, "--dialect fanuc");
  CHECK(m.code == 0);
  check_points(m, m.ends,
               {{0, -20, 0}, {-3, 0, 0}, {0, 3, 0}, {50, 3, 0}, {100, 1.5, 0}, {100, -20, 0}});
  const CliMoves l = cli_moves(file, "");
  CHECK(l.code == 1);
  CHECK(l.out.find("cutter radius compensation is already on") != std::string::npos);
}

TEST_CASE("fanuc-modal: #4011 #4016 #4017 read the transforms in force (B-63534EN II-15.2)") {
  // Modal information: #4011 G50/G51, #4016 G68/G69, #4017 G15/G16 of the blocks before.
  const std::string file = modal_program("modal_vars.nc",
                                         "G21 G90 G17\n"
                                         "#1 = #4011 * 10000 + #4016 * 100 + #4017\n"
                                         "G51 X0 Y0 Z0 P1.\n"
                                         "G68 X0 Y0 R0.\n"
                                         "G16\n"
                                         "#2 = #4011 * 10000 + #4016 * 100 + #4017\n"
                                         "G15 G69 G50\n"
                                         "G0 X#1 Y#2\n"
                                         "M30\n");
  const CliMoves m = cli_moves(file, "--dialect fanuc");
  CHECK(m.code == 0);
  check_points(m, m.ends, {{506915, 516816, 0}});
}

TEST_CASE(
    "fanuc-modal: G66 modal macro call after each move, G67 cancels (Mitsubishi M700V "
    "13.5, modal call A)") {
  // Mitsubishi M700V 13.5 "User macro specifications": with modal call A (G66) the macro is
  // called every time a movement command is executed; YASNAC LX3 2.8.23.1: G66 modal call, G67
  // cancel. Arguments as G65's (specification I): R #18, Z #26. Not in the macro's own moves.
  const std::string file = modal_program("g66.nc",
                                         "O0001\n"
                                         "G21 G90 G17\n"
                                         "G0 X0 Y0 Z10.\n"
                                         "G66 P9100 R2. Z-5.\n"
                                         "X10. Y10.\n"
                                         "X20.\n"
                                         "G67\n"
                                         "X30.\n"
                                         "M30\n"
                                         "O9100\n"
                                         "G1 Z#26 F100.\n"
                                         "G0 Z#18\n"
                                         "M99\n");
  const CliMoves m = cli_moves(file, "--dialect fanuc");
  CHECK(m.code == 0);
  check_points(m, m.ends,
               {{0, 0, 10},
                {10, 10, 10},
                {10, 10, -5},
                {10, 10, 2},
                {20, 10, 2},
                {20, 10, -5},
                {20, 10, 2},
                {30, 10, 2}});
  CHECK(m.kinds[2] == "line");
  const std::string l2 = modal_program("g66_l.nc", "G66 P9100 L2 R2.\nM30\n");
  const CliMoves e = cli_moves(l2, "--dialect fanuc");
  CHECK(e.code == 1);
  CHECK(e.out.find("G66 L (repeats of each call) is not read") != std::string::npos);
}
