// Fanuc/Haas lathe conventions (--dialect fanuc on a lathe machine): each test names the public
// document and the section it reproduces; the expected moves are worked by hand.
#include <catch2/catch.hpp>

#include "interp/lathe_fanuc.hpp"
#include "interp/program.hpp"
#include "machine/machine_file.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

// A lathe: the default machine's X Y Z (the program uses X and Z), kind = "lathe", with tools
// 1 (X 0.5 Z 2) and 2 (X -1.25 Z 3.5).
gm::Machine lathe_machine() {
  gm::Machine m;
  m.lathe = true;
  m.tool_table = gm::ToolTable{};
  m.tool_table.source = "<test>";
  for (const auto& [n, x, z] : {std::tuple{1, 0.5, 2.0}, std::tuple{2, -1.25, 3.5}}) {
    gm::ToolEntry e;
    e.number = e.pocket = n;
    e.offset_mm[0] = x;
    e.offset_mm[2] = z;
    m.tool_table.tools.push_back(e);
  }
  return m;
}

gm::InterpreterOptions fanuc(const gm::Machine& m) {
  gm::InterpreterOptions o{&m, false};
  o.dialect = gm::Dialect::Fanuc;
  return o;
}

std::vector<gm::Canon> lathe_run(const std::string& program, const gm::Machine& m) {
  std::istringstream in(program);
  gm::ProgramStream s(in, "lathe.nc", fanuc(m));
  std::vector<gm::Canon> out;
  gm::Canon c;
  while (s.next(c)) out.push_back(c);
  return out;
}

std::vector<gm::Motion> lathe_moves(const std::string& program,
                                    const gm::Machine& m = lathe_machine()) {
  std::vector<gm::Motion> out;
  for (const auto& c : lathe_run(program, m))
    if (const auto* mo = std::get_if<gm::Motion>(&c)) out.push_back(*mo);
  return out;
}

std::vector<gm::Diagnostic> lathe_check(const std::string& program,
                                        const gm::Machine& m = lathe_machine()) {
  std::istringstream in(program);
  std::vector<gm::Diagnostic> d;
  gm::check_program_diagnostics(in, "lathe.nc", fanuc(m), d);
  return d;
}

std::size_t errors(const std::vector<gm::Diagnostic>& d) {
  std::size_t n = 0;
  for (const auto& x : d) n += x.severity == gm::Severity::Error ? 1 : 0;
  return n;
}

// The end of a move in the ZX plane: {Z, X radius}, machine coordinates (mm).
struct ZX {
  double z, x;
};
ZX end_of(const gm::Motion& m) {
  return ZX{m.end_mm[2], m.end_mm[0]};
}
void require_end(const gm::Motion& m, gm::MotionKind kind, double z, double x_radius) {
  INFO("line " << m.line << " end Z" << m.end_mm[2] << " X(r)" << m.end_mm[0]);
  CHECK(m.kind == kind);
  CHECK(end_of(m).z == Approx(z).margin(1e-9));
  CHECK(end_of(m).x == Approx(x_radius).margin(1e-9));
}

}  // namespace

// "CONCISE GUIDE FANUC" (Robur Line F1 series specifications, p. 48: "X will be equal to the
// diameter of the blank workpiece"); zanotowane.pl "G71 Stock Removal" (U(2) "(Diameter
// value)"): X and U are diameters on a Fanuc lathe, U/W incremental X/Z.
TEST_CASE("lathe-fanuc: X is a diameter, U and W are incremental X and Z") {
  const auto mv = lathe_moves("G98 G0 X40 Z2\nU-10 W-5\nG1 U4 Z-20 F100\nM30\n");
  REQUIRE(mv.size() == 3);
  require_end(mv[0], gm::MotionKind::Rapid, 2.0, 20.0);   // X40: radius 20
  require_end(mv[1], gm::MotionKind::Rapid, -3.0, 15.0);  // X30, Z-3
  require_end(mv[2], gm::MotionKind::Line, -20.0, 17.0);  // X34, Z-20
  // Under --dialect linuxcnc the same machine reads X as a radius and has no U axis.
  gm::Machine m = lathe_machine();
  std::istringstream in("G0 X40 Z2\nM30\n");
  gm::ProgramStream s(in, "lathe.nc", gm::InterpreterOptions{&m, false});
  gm::Canon c;
  double x = -1;
  while (s.next(c))
    if (const auto* mo = std::get_if<gm::Motion>(&c)) x = mo->end_mm[0];
  CHECK(x == 40.0);
}

TEST_CASE("lathe-fanuc: U and X in one block is an error at U") {
  const auto d = lathe_check("G0 X40 Z2\nG1 X30 U-2 F100\nM30\n");
  REQUIRE(errors(d) == 1);
  CHECK(d[0].code == static_cast<int>(gm::ErrorCode::DuplicateWord));
  CHECK(d[0].loc.line == 2);
  CHECK(d[0].loc.column == 8);
  CHECK(d[0].message.find("U and X in one block") != std::string::npos);
  // A lathe only under fanuc: a mill machine reads U as an axis it lacks.
  const auto mill = lathe_check("G0 U1\nM30\n", gm::Machine{});
  REQUIRE(errors(mill) == 1);
  CHECK(mill[0].code == static_cast<int>(gm::ErrorCode::AxisUnavailable));
}

// cncprogramminghub.com "What is T0101 in CNC programming?": T0101 tool 1 with offset 1, the
// offset active when the command is read; T0100 selects tool 1 and cancels the offsets. The
// turret indexes with the spindle turning.
TEST_CASE("lathe-fanuc: T0101 changes the tool and applies offset 01, T0100 cancels it") {
  const auto run = lathe_run("M3 S500\nT0101\nG0 X40 Z2\nT0100\nG0 X40 Z2\nT0202\nG0 X40 Z2\nM30\n",
                             lathe_machine());
  bool stopped = false;
  for (const auto& c : run)
    if (const auto* e = std::get_if<gm::Event>(&c);
        e && e->kind == gm::EventKind::SpindleStop && e->line < 8)  // M30 (line 8) stops it
      stopped = true;
  CHECK_FALSE(stopped);
  std::vector<int> changed;
  std::vector<gm::Motion> mv;
  for (const auto& c : run) {
    if (const auto* e = std::get_if<gm::Event>(&c); e && e->kind == gm::EventKind::ToolNumber)
      changed.push_back(e->index);
    if (const auto* mo = std::get_if<gm::Motion>(&c)) mv.push_back(*mo);
  }
  CHECK(changed == std::vector<int>{1, 1, 2});
  REQUIRE(mv.size() == 3);
  require_end(mv[0], gm::MotionKind::Rapid, 2.0 + 2.0, 20.0 + 0.5);   // offset 1 applied
  require_end(mv[1], gm::MotionKind::Rapid, 2.0, 20.0);               // T0100: none
  require_end(mv[2], gm::MotionKind::Rapid, 2.0 + 3.5, 20.0 - 1.25);  // offset 2
}

// expertsmind.com "Speed Function" ("N020 G50 S4500 maximum spindle rpm is 4500"); docs.edingcnc
// "G96, G97 (Spindle Control Mode)" (RPM = S / (2 pi X), S in m/min in G21).
TEST_CASE("lathe-fanuc: G50 S clamps G96's spindle speed") {
  const auto mv = lathe_moves("G50 S2000\nG96 S200 M3\nG0 X52 Z2\nG99 G1 X20 F0.2\nM30\n");
  REQUIRE(mv.size() == 2);
  const gm::Motion& cut = mv[1];
  CHECK(cut.css_surface_mm_min == Approx(200000.0));
  CHECK(cut.css_max_rpm == Approx(2000.0));
  // At diameter 52 (radius 26): 200 m/min / (pi * 0.052 m) = 1224.3 rpm; at diameter 20 the
  // formula gives 3183 rpm, so the clamp's 2000.
  CHECK(cut.spindle_rpm_at(26.0) == Approx(200000.0 / (2 * M_PI * 26.0)));
  CHECK(cut.spindle_rpm_at(10.0) == Approx(2000.0));
  CHECK(cut.mm_per_rev == Approx(0.2));
  // A later G50 S under G96 changes the cap at once.
  const auto later = lathe_moves("G96 S200 M3\nG0 X52 Z2\nG50 S1500\nG99 G1 X20 F0.2\nM30\n");
  REQUIRE(later.size() == 2);
  CHECK(later[1].css_max_rpm == Approx(1500.0));
}

// the-vms.com glossary "feed per minute mode": on a lathe G98 is feed per minute and G99 feed
// per revolution (G99 G01 X1 Z1 F.02: .020 per revolution).
TEST_CASE("lathe-fanuc: G99 feeds per revolution, G98 per minute") {
  const auto mv = lathe_moves("G97 S1000 M3\nG0 X40 Z2\nG99 G1 Z-10 F0.2\nG98 G1 Z-20 F150\nM30\n");
  REQUIRE(mv.size() == 3);
  CHECK(mv[1].mm_per_rev == Approx(0.2));
  CHECK(mv[1].feed_mm_min == Approx(200.0));  // 0.2 mm/rev x 1000 rpm
  CHECK(mv[2].mm_per_rev == 0.0);
  CHECK(mv[2].feed_mm_min == Approx(150.0));
}

TEST_CASE("lathe-fanuc: G50 X Z sets the coordinates as G92, G28 U0 W0 homes from here") {
  const auto mv = lathe_moves("G0 X40 Z10\nG50 X100 Z50\nG0 X80 Z40\nG28 U0 W0\nM30\n");
  REQUIRE(mv.size() == 3);
  require_end(mv[1], gm::MotionKind::Rapid, 0.0, 10.0);  // 10 radius and 10 in Z less
  require_end(mv[2], gm::MotionKind::Rapid, 0.0, 0.0);   // the G28 position (machine zero)
}

// zanotowane.pl "G71 Stock Removal in X axis" (the format: G71 U(depth, radius) R(escape);
// G71 P ns Q nf U(allowance, diameter) W F); "CONCISE GUIDE FANUC" (Robur) p. 48: each cut
// starts at the start point's Z, the tool escapes at 45 degrees by R and returns in rapid to
// the Z start; after the roughing cuts a cut along the profile leaves the allowances, then a
// rapid back to the start point.
TEST_CASE("lathe-fanuc: G71 roughing, layers worked by hand") {
  const std::string prog =
      "G98 G0 X40 Z2\n"
      "G71 U3 R1\n"
      "G71 P10 Q20 F300\n"
      "N10 G0 X10\n"
      "G1 Z-20 F150\n"
      "X30 Z-30\n"
      "N20 X40\n"
      "G0 X60\n"
      "M30\n";
  const auto mv = lathe_moves(prog);
  // Start A: Z2, radius 20. Profile: (Z2, r5) (Z-20, r5) (Z-30, r15) (Z-30, r20). Layers every
  // 3 mm of radius from r20: r17 r14 r11 r8 (r5 is the profile's own start).
  REQUIRE(mv.size() == 1 + 4 * 4 + 4 + 1 + 1);
  using K = gm::MotionKind;
  // r17: the profile reaches r17 on its last element, at Z-30.
  require_end(mv[1], K::Rapid, 2.0, 17.0);
  require_end(mv[2], K::Line, -30.0, 17.0);
  CHECK(mv[2].feed_mm_min == Approx(300.0));
  require_end(mv[3], K::Rapid, -29.0, 18.0);  // 45 degrees off by R1
  require_end(mv[4], K::Rapid, 2.0, 18.0);
  // r14 meets the taper (Z-20, r5)-(Z-30, r15) at Z = -20 - (14 - 5) = -29.
  require_end(mv[5], K::Rapid, 2.0, 14.0);
  require_end(mv[6], K::Line, -29.0, 14.0);
  require_end(mv[7], K::Rapid, -28.0, 15.0);
  // r11: Z-26; r8: Z-23.
  require_end(mv[10], K::Line, -26.0, 11.0);
  require_end(mv[14], K::Line, -23.0, 8.0);
  require_end(mv[16], K::Rapid, 2.0, 9.0);
  // The pass along the profile (no allowance here) and back to A.
  require_end(mv[17], K::Rapid, 2.0, 5.0);
  require_end(mv[18], K::Line, -20.0, 5.0);
  require_end(mv[19], K::Line, -30.0, 15.0);
  require_end(mv[20], K::Line, -30.0, 20.0);
  require_end(mv[21], K::Rapid, 2.0, 20.0);
  // The cycle's moves are its line's; the profile blocks did not run (the next move is G0 X60
  // from A).
  CHECK(mv[1].line == 3);
  require_end(mv[22], K::Rapid, 2.0, 30.0);
}

TEST_CASE("lathe-fanuc: G71 allowances U (diameter) and W shift the profile") {
  const std::string prog =
      "G98 G0 X40 Z2\n"
      "G71 U6 R1\n"
      "G71 P10 Q20 U1 W0.2 F300\n"
      "N10 G0 X10\n"
      "G1 Z-20\n"
      "N20 X40\n"
      "M30\n";
  const auto mv = lathe_moves(prog);
  // Shifted profile: (Z2.2, r5.5) (Z-19.8, r5.5) (Z-19.8, r20.5). Layers r14 r8 (r20 - 6k >
  // 5.5): each ends at the shoulder Z-19.8.
  using K = gm::MotionKind;
  REQUIRE(mv.size() == 1 + 2 * 4 + 3 + 1);
  require_end(mv[2], K::Line, -19.8, 14.0);
  require_end(mv[6], K::Line, -19.8, 8.0);
  require_end(mv[9], K::Rapid, 2.2, 5.5);
  require_end(mv[10], K::Line, -19.8, 5.5);
  require_end(mv[11], K::Line, -19.8, 20.5);
  require_end(mv[12], K::Rapid, 2.0, 20.0);
}

// scribd "G71 O.D./I.D. Stock Removal Cycle (Group 00)" (Haas G-code pages): "Usually a G70 call
// to the same PQ block definition is used to finish the shape"; zanotowane.pl: F and S between
// the start and end blocks "will only be effective on the finishing pass".
TEST_CASE("lathe-fanuc: G70 finishes along the profile above it at the profile's feed") {
  const std::string prog =
      "G98 G0 X40 Z2\n"
      "G71 U6 R1\n"
      "G71 P10 Q20 F300\n"
      "N10 G0 X10\n"
      "G1 Z-20 F120\n"
      "G2 X30 Z-30 R10\n"
      "N20 G1 X40\n"
      "G0 X44 Z4\n"
      "G70 P10 Q20\n"
      "G0 X60\n"
      "M30\n";
  const auto mv = lathe_moves(prog);
  // The G70 moves are line 9's: from (Z4, r22) to the profile (N10 moves X only: Z stays the
  // start point's), along it, back.
  std::vector<gm::Motion> g70;
  for (const auto& m : mv)
    if (m.line == 9) g70.push_back(m);
  using K = gm::MotionKind;
  REQUIRE(g70.size() == 5);
  require_end(g70[0], K::Rapid, 4.0, 5.0);
  require_end(g70[1], K::Line, -20.0, 5.0);
  CHECK(g70[1].feed_mm_min == Approx(120.0));
  require_end(g70[2], K::Arc, -30.0, 15.0);
  CHECK_FALSE(g70[2].ccw);
  CHECK(g70[2].center_mm[2] == Approx(-20.0));  // R10 from (Z-20, r5) clockwise: centre r15
  CHECK(g70[2].center_mm[0] == Approx(15.0));
  require_end(g70[3], K::Line, -30.0, 20.0);
  require_end(g70[4], K::Rapid, 4.0, 22.0);
  // After G70 the program goes on after its line.
  require_end(mv.back(), K::Rapid, 4.0, 30.0);
}

TEST_CASE("lathe-fanuc: cycle errors are located and specific") {
  SECTION("missing Q") {
    const auto d = lathe_check("G0 X40 Z2\nG71 U2 R1\nG71 P10 F300\nN10 G0 X10\nM30\n");
    REQUIRE(errors(d) >= 1);
    CHECK(d[0].loc.line == 3);
    CHECK(d[0].message.find("Q") != std::string::npos);
  }
  SECTION("no block N ns") {
    const auto d = lathe_check("G0 X40 Z2\nG71 U2 R1\nG71 P10 Q20 F300\nN11 G0 X10\nM30\n");
    REQUIRE(errors(d) == 1);
    CHECK(d[0].loc.line == 3);
    CHECK(d[0].message.find("no block N10") != std::string::npos);
  }
  SECTION("profile not monotone, at its line") {
    const auto d = lathe_check(
        "G98 G0 X40 Z2\nG71 U2 R1\nG71 P10 Q20 F300\nN10 G0 X10\nG1 Z-10\nX20\nX16 Z-20\n"
        "N20 X40\nM30\n");
    REQUIRE(errors(d) == 1);
    CHECK(d[0].loc.line == 7);
    CHECK(d[0].message.find("not monotone") != std::string::npos);
  }
  SECTION("a depth of cut that would make too many layers") {
    const auto d = lathe_check(
        "G98 G0 X40 Z2\nG71 U0.00001 R0\nG71 P10 Q20 F300\nN10 G0 X10\nG1 Z-10\nN20 X40\nM30\n");
    REQUIRE(errors(d) == 1);
    CHECK(d[0].loc.line == 3);
    CHECK(d[0].message.find("layers") != std::string::npos);
  }
  SECTION("the first profile block must move in G00 or G01") {
    const auto d =
        lathe_check("G98 G0 X40 Z2\nG71 U2 R1\nG71 P10 Q20 F300\nN10 X10\nG1 Z-10\nN20 X40\nM30\n");
    REQUIRE(errors(d) >= 1);
    CHECK(d[0].loc.line == 4);
  }
}

// industrialmonitordirect.com "Fanuc OT G76 Threading Cycle Programming Guide" (two-line
// syntax: G76 P m aa Q dmin R d; G76 X Z R i P k Q d F L, P and Q in the least increment);
// cadem.com "G76 Fanuc threading cycle" (constant cutting area: the n-th cut at depth d x sqrt n)
// and the Q-is-the-minimum-depth answer quoted there.
TEST_CASE("lathe-fanuc: G76 two-block threading, depths by hand") {
  const std::string prog =
      "G97 S500 M3\n"
      "G0 X30 Z5\n"
      "G76 P010000 Q100 R0\n"
      "G76 X20 Z-20 P1000 Q400 F2\n"
      "M30\n";
  const auto mv = lathe_moves(prog);
  // Height 1.0, first depth 0.4, minimum step 0.1: 0.4, 0.4 sqrt2, 0.4 sqrt3, 0.8, then
  // 0.4 sqrt5 = 0.894 is less than 0.1 deeper, so 0.9; then 1.0, and the finishing pass.
  const std::vector<double> depths{0.4, 0.4 * std::sqrt(2.0), 0.4 * std::sqrt(3.0), 0.8, 0.9, 1.0,
                                   1.0};
  std::vector<gm::Motion> threads;
  for (const auto& m : mv)
    if (m.spindle_synced) threads.push_back(m);
  REQUIRE(threads.size() == depths.size());
  for (std::size_t i = 0; i < depths.size(); ++i) {
    // The crest is 1.0 above the root radius 10: a pass at depth d cuts at radius 11 - d.
    require_end(threads[i], gm::MotionKind::Line, -20.0, 11.0 - depths[i]);
    CHECK(threads[i].start_mm[0] == Approx(11.0 - depths[i]));
    CHECK(threads[i].start_mm[2] == Approx(5.0));  // angle 0: straight in
    CHECK(threads[i].mm_per_rev == Approx(2.0));
  }
  require_end(mv.back(), gm::MotionKind::Rapid, 5.0, 15.0);
}

TEST_CASE("lathe-fanuc: G76 with a 60 degree tool moves in along the flank") {
  const auto mv =
      lathe_moves("G97 S500 M3\nG0 X30 Z5\nG76 P010060 Q100 R0\nG76 X20 Z-20 P1000 Q400 F2\nM30\n");
  std::vector<gm::Motion> threads;
  for (const auto& m : mv)
    if (m.spindle_synced) threads.push_back(m);
  REQUIRE(threads.size() == 7);
  // The start moves towards the cut (-Z) by depth x tan 30.
  CHECK(threads[0].start_mm[2] == Approx(5.0 - 0.4 * std::tan(M_PI / 6)));
  CHECK(threads[6].start_mm[2] == Approx(5.0 - 1.0 * std::tan(M_PI / 6)));
}

// The bundled Fanuc lathe program: runs without a diagnostic on programs/machines/lathe.toml,
// the same with the program read ahead on a second thread (G70 re-reads its profile above).
TEST_CASE("lathe-fanuc: the bundled shaft program, read ahead or not") {
  const std::string dir = std::string(GMOTION_TESTS_DIR) + "/../programs/";
  const gm::Machine m = gm::load_machine_file(dir + "machines/lathe.toml");
  CHECK(m.lathe);
  CHECK(m.dialect == "fanuc");
  auto ends = [&](bool ahead) {
    std::ifstream in(dir + "dialects/fanuc_lathe_shaft.nc", std::ios::binary);
    gm::InterpreterOptions o = fanuc(m);
    o.read_ahead = ahead;
    gm::ProgramStream s(in, "fanuc_lathe_shaft.nc", o);
    std::vector<std::array<double, 3>> out;
    gm::Canon c;
    while (s.next(c))
      if (const auto* mo = std::get_if<gm::Motion>(&c))
        out.push_back({static_cast<double>(mo->line), mo->end_mm[0], mo->end_mm[1]});
    return out;
  };
  const auto one = ends(false);
  CHECK(one == ends(true));
  std::ifstream in(dir + "dialects/fanuc_lathe_shaft.nc", std::ios::binary);
  std::vector<gm::Diagnostic> d;
  gm::check_program_diagnostics(in, "fanuc_lathe_shaft.nc", fanuc(m), d);
  CHECK(d.empty());
  // G71 (line 12), G70 (line 25) and G76 (line 32) each made moves.
  for (const double line : {12.0, 25.0, 32.0})
    CHECK(std::count_if(one.begin(), one.end(), [&](const auto& e) { return e[0] == line; }) > 3);
}

// The bundled single-cycle program: G94 faces twice, G90 roughs three passes and a taper, G92
// threads M30 x 1.5 in five passes (one block each, X alone after the first). Tool 1's offsets
// are 0; tool 3's (X 2, Z -1.5) shift the machine position of the thread passes.
TEST_CASE("lathe-fanuc: the bundled single-cycle pin program, moves by hand") {
  const std::string dir = std::string(GMOTION_TESTS_DIR) + "/../programs/";
  const gm::Machine m = gm::load_machine_file(dir + "machines/lathe.toml");
  std::ifstream in(dir + "dialects/fanuc_lathe_pin.nc", std::ios::binary);
  gm::ProgramStream s(in, "fanuc_lathe_pin.nc", fanuc(m));
  std::vector<gm::Motion> mv;
  gm::Canon c;
  while (s.next(c))
    if (const auto* mo = std::get_if<gm::Motion>(&c)) mv.push_back(*mo);
  // 2 G94 + 4 G90 + 5 G92 cycles of 4 moves, 5 G00 blocks, the last G28's one move home.
  REQUIRE(mv.size() == 11 * 4 + 5 + 1);
  using K = gm::MotionKind;
  require_end(mv[1], K::Rapid, 1.0, 22.0);    // N70 G94 from (Z3, r22): in Z to Z1
  require_end(mv[2], K::Line, 1.0, -0.8);     // the face to X-1.6
  require_end(mv[6], K::Line, 0.0, -0.8);     // N80 Z0.: the cycle again
  require_end(mv[11], K::Line, -40.0, 19.0);  // N100 G90 X38. from (Z2, r22)
  require_end(mv[19], K::Line, -40.0, 15.2);  // N120 X30.4
  require_end(mv[22], K::Rapid, 2.0, 13.2);   // N130 R-2.: the taper starts at r15.2 - 2
  require_end(mv[23], K::Line, -15.0, 15.2);
  // N230 X28.16, the last pass: r14.08 with tool 3's X offset 2, Z-32 with its Z offset -1.5.
  const gm::Motion& last = mv[45];  // (the G92 cycles are moves 28-47)
  require_end(last, K::Line, -32.0 - 1.5, 14.08 + 2.0);
  CHECK(last.spindle_synced);
  CHECK(last.mm_per_rev == Approx(1.5));
  CHECK(last.line == 28);
}

// cncprograming.blogspot.com "G72" (G72 W(cutting depth) R(escape); P Q U W F as G71);
// zanotowane.pl "G72": G71's cycle with the cuts along the other axis.
TEST_CASE("lathe-fanuc: G72 facing, layers along Z worked by hand") {
  const auto mv = lathe_moves(
      "G98 G0 X84 Z2\nG72 W2 R0.5\nG72 P10 Q20 F200\nN10 G0 Z-6\nG1 X40\nZ-2\nN20 X0\nM30\n");
  // Start A: Z2, r42. Profile (Z-6, r42) (Z-6, r20) (Z-2, r20) (Z-2, r0). Layers every 2 mm
  // of Z from Z2: Z0 (across the whole face: the profile never rises to it), Z-2, Z-4 (both
  // end at the step, r20); Z-6 is the profile's own start.
  using K = gm::MotionKind;
  REQUIRE(mv.size() == 1 + 3 * 4 + 4 + 1);
  require_end(mv[1], K::Rapid, 0.0, 42.0);
  require_end(mv[2], K::Line, 0.0, 0.0);
  CHECK(mv[2].feed_mm_min == Approx(200.0));
  require_end(mv[3], K::Rapid, 0.5, 0.5);
  require_end(mv[4], K::Rapid, 0.5, 42.0);
  require_end(mv[5], K::Rapid, -2.0, 42.0);
  require_end(mv[6], K::Line, -2.0, 20.0);
  require_end(mv[7], K::Rapid, -1.5, 20.5);
  require_end(mv[10], K::Line, -4.0, 20.0);
  require_end(mv[13], K::Rapid, -6.0, 42.0);
  require_end(mv[14], K::Line, -6.0, 20.0);
  require_end(mv[15], K::Line, -2.0, 20.0);
  require_end(mv[16], K::Line, -2.0, 0.0);
  require_end(mv[17], K::Rapid, 2.0, 42.0);
}

TEST_CASE("lathe-fanuc: G32 threads as G33") {
  const auto mv = lathe_moves("G97 S500 M3\nG0 X20 Z5\nG32 Z-20 F1.5\nM30\n");
  REQUIRE(mv.size() == 2);
  CHECK(mv[1].spindle_synced);
  CHECK(mv[1].mm_per_rev == Approx(1.5));
  require_end(mv[1], gm::MotionKind::Line, -20.0, 10.0);
}

// zanotowane.pl "G90 canned cycle taper cutting" (G90 X(U) Z(W) R F: one pass, "only the values
// that change need to be entered in the next block"); HUST H6D-T manual 3-41 "Face Cutting Fixed
// Cycle, G94" ("G90, G94, G92 are modal codes and all the values for X(U), Z(W) and R remain
// valid unless they are redefined or another G-command is given"); en.cncforum.net "G92 Cycle
// Basic Threading" (G92 X Z R F, F the lead). The G90 path: rapid in X to the cut's start (the
// end's X plus R, a radius), feed to the end, feed out in X to the start's X, rapid back in Z.
TEST_CASE("lathe-fanuc: G90 cutting cycle, straight, repeated by X alone and tapered by R") {
  using K = gm::MotionKind;
  const auto mv = lathe_moves("G98 G0 X50 Z2\nG90 X40 Z-20 F100\nX30\nU-25 R-2\nG0 X60 Z5\nM30\n");
  // Start A: Z2, r25.
  REQUIRE(mv.size() == 1 + 3 * 4 + 1);
  require_end(mv[1], K::Rapid, 2.0, 20.0);
  require_end(mv[2], K::Line, -20.0, 20.0);
  CHECK(mv[2].feed_mm_min == Approx(100.0));
  require_end(mv[3], K::Line, -20.0, 25.0);
  CHECK(mv[3].feed_mm_min == Approx(100.0));
  require_end(mv[4], K::Rapid, 2.0, 25.0);
  CHECK(mv[1].line == 2);
  // X30 alone: the same cycle to r15, Z-20 kept.
  require_end(mv[5], K::Rapid, 2.0, 15.0);
  require_end(mv[6], K::Line, -20.0, 15.0);
  CHECK(mv[6].feed_mm_min == Approx(100.0));
  require_end(mv[7], K::Line, -20.0, 25.0);
  require_end(mv[8], K::Rapid, 2.0, 25.0);
  CHECK(mv[5].line == 3);
  // U-25 from A (a diameter): the end r25 - 12.5 = r12.5; R-2: the cut starts at r10.5.
  require_end(mv[9], K::Rapid, 2.0, 10.5);
  require_end(mv[10], K::Line, -20.0, 12.5);
  require_end(mv[11], K::Line, -20.0, 25.0);
  require_end(mv[12], K::Rapid, 2.0, 25.0);
  // G0 cancels the cycle: X60 Z5 is a rapid.
  require_end(mv[13], K::Rapid, 5.0, 30.0);
  CHECK(mv.back().line == 5);
}

// ADT-CNC4620 Programming Manual 3.5.3 "Radial cutting cycle G94" (G94 X/U Z/W R F; R the
// difference in Z between the cut's start and end; the way out in Z fed (G1), then a rapid back;
// G94 is modal); HUST H6D-T 3-41 (the values stay valid for the next blocks).
TEST_CASE("lathe-fanuc: G94 end face cutting, repeated by Z alone and tapered by R") {
  using K = gm::MotionKind;
  const auto mv = lathe_moves("G98 G0 X30 Z5\nG94 X10 Z-1 F80\nZ-2 R-3\nG0 X40\nM30\n");
  // Start A: Z5, r15.
  REQUIRE(mv.size() == 1 + 2 * 4 + 1);
  require_end(mv[1], K::Rapid, -1.0, 15.0);
  require_end(mv[2], K::Line, -1.0, 5.0);
  CHECK(mv[2].feed_mm_min == Approx(80.0));
  require_end(mv[3], K::Line, 5.0, 5.0);
  require_end(mv[4], K::Rapid, 5.0, 15.0);
  // Z-2 R-3: the face from (Z-5, r15) to (Z-2, r5).
  require_end(mv[5], K::Rapid, -5.0, 15.0);
  require_end(mv[6], K::Line, -2.0, 5.0);
  require_end(mv[7], K::Line, 5.0, 5.0);
  require_end(mv[8], K::Rapid, 5.0, 15.0);
  require_end(mv[9], K::Rapid, 5.0, 20.0);
}

// en.cncforum.net "CNC Lathe | G92 Cycle | Basic Threading" (G92 X.. Z.. R.. F..: X the pass's
// diameter, Z the thread's end, F the lead; each pass one block, the next passes X alone); the
// path as G90's with the cut spindle-synchronised as G32 and the way out a rapid.
TEST_CASE("lathe-fanuc: G92 threading cycle, one pass a block") {
  using K = gm::MotionKind;
  const auto mv = lathe_moves("G97 S500 M3\nG0 X24 Z5\nG92 X19.2 Z-20 F1.5\nX18.6\nG0 X30\nM30\n");
  REQUIRE(mv.size() == 1 + 2 * 4 + 1);
  require_end(mv[1], K::Rapid, 5.0, 9.6);
  require_end(mv[2], K::Line, -20.0, 9.6);
  CHECK(mv[2].spindle_synced);
  CHECK(mv[2].mm_per_rev == Approx(1.5));
  require_end(mv[3], K::Rapid, -20.0, 12.0);
  require_end(mv[4], K::Rapid, 5.0, 12.0);
  // X18.6: the next pass at r9.3, the lead kept.
  require_end(mv[5], K::Rapid, 5.0, 9.3);
  require_end(mv[6], K::Line, -20.0, 9.3);
  CHECK(mv[6].spindle_synced);
  CHECK(mv[6].mm_per_rev == Approx(1.5));
  require_end(mv[8], K::Rapid, 5.0, 12.0);
  require_end(mv[9], K::Rapid, 5.0, 15.0);
  // A taper thread: R1 (radius) the start 1 mm above the end.
  const auto taper = lathe_moves("G97 S500 M3\nG0 X24 Z5\nG92 X19 Z-20 R1 F2\nM30\n");
  REQUIRE(taper.size() == 1 + 4);
  require_end(taper[1], K::Rapid, 5.0, 10.5);
  require_end(taper[2], K::Line, -20.0, 9.5);
  CHECK(taper[2].mm_per_rev == Approx(2.0));
}

TEST_CASE("lathe-fanuc: single cycle modes and their errors") {
  SECTION("G90 without axis words selects the cycle; G50 and G28 keep their own X Z") {
    using K = gm::MotionKind;
    const auto mv =
        lathe_moves("G98 G0 X50 Z2\nG90 F100\nX40 Z-10\nG28 U0 W0\nG0 X50 Z2\nX44\nM30\n");
    // G28 U0 W0: the intermediate point is where the tool is, then machine zero (one move).
    REQUIRE(mv.size() == 1 + 4 + 1 + 1 + 1);
    require_end(mv[2], K::Line, -10.0, 20.0);
    CHECK(mv[2].feed_mm_min == Approx(100.0));
    require_end(mv[5], K::Rapid, 0.0, 0.0);
    require_end(mv[6], K::Rapid, 2.0, 25.0);
    require_end(mv[7], K::Rapid, 2.0, 22.0);  // G0 cancelled the cycle: X44 is a rapid
  }
  SECTION("G91 is not a lathe code") {
    const auto d = lathe_check("G0 X40 Z2\nG91 G0 U-2\nM30\n");
    REQUIRE(errors(d) == 1);
    CHECK(d[0].code == static_cast<int>(gm::ErrorCode::NotInDialect));
    CHECK(d[0].loc.line == 2);
    CHECK(d[0].loc.column == 1);
    CHECK(d[0].message.find("U and W") != std::string::npos);
  }
  SECTION("two group 1 codes in one block") {
    const auto d = lathe_check("G0 X40 Z2\nG90 G01 X30 Z-10 F100\nM30\n");
    REQUIRE(errors(d) == 1);
    CHECK(d[0].code == static_cast<int>(gm::ErrorCode::ModalGroupViolation));
    CHECK(d[0].loc.line == 2);
    CHECK(d[0].loc.column == 5);
  }
  SECTION("the first cycle block needs X and Z") {
    const auto d = lathe_check("G0 X40 Z2\nG90 X30 F100\nM30\n");
    REQUIRE(errors(d) == 1);
    CHECK(d[0].code == static_cast<int>(gm::ErrorCode::MissingWord));
    CHECK(d[0].message.find("G90 without Z (W)") != std::string::npos);
  }
  SECTION("G92 needs the lead") {
    const auto d = lathe_check("G97 S500 M3\nG0 X24 Z5\nG92 X19 Z-20\nM30\n");
    REQUIRE(errors(d) == 1);
    CHECK(d[0].message.find("lead") != std::string::npos);
  }
  SECTION("a word the cycle does not take, at the word") {
    const auto d = lathe_check("G0 X40 Z2\nG94 X10 Z-1 F80 M8\nM30\n");
    REQUIRE(errors(d) == 1);
    CHECK(d[0].code == static_cast<int>(gm::ErrorCode::UnusedWord));
    CHECK(d[0].loc.column == 17);
  }
  SECTION("tool nose radius compensation is refused") {
    gm::Machine m = lathe_machine();
    m.tool_table.tools[0].diameter_mm = 1.6;  // a nose radius 0.8
    const auto d =
        lathe_check("G98 T0101\nG0 X40 Z2\nG42 D1 G1 X36 Z1 F100\nG90 X30 Z-10\nM30\n", m);
    REQUIRE(errors(d) == 1);
    CHECK(d[0].code == static_cast<int>(gm::ErrorCode::CutterCompMisused));
    CHECK(d[0].loc.line == 4);
  }
  SECTION("G71 with a pocket names the type II rule") {
    const auto d = lathe_check(
        "G98 G0 X40 Z2\nG71 U2 R1\nG71 P10 Q20 F300\nN10 G0 X10 Z2\nG1 Z-10\nX20\nX16 "
        "Z-20\nN20 X40\nM30\n");
    REQUIRE(errors(d) == 1);
    CHECK(d[0].loc.line == 7);
    CHECK(d[0].message.find("type II") != std::string::npos);
  }
}

// ADT-CNC4620 Programming Manual, "G73" execution process (manual pp. 48-49): A to A1 rapid;
// each roughing cycle A_k, B_k, C_k along the ns-nf blocks in their own modes at the G73 line's
// F, then C_k to A_(k+1) rapid; after the n-th, C_n to A rapid; F in the profile only for G70.
// zanotowane.pl "G73 Pattern Repeat Cycle" (G73 U W R; G73 P Q U(diameter) W F). The relief
// shrinks evenly from Δi, Δk on the first pass to 0 on the d-th, which cuts at the allowance.
TEST_CASE("lathe-fanuc: G73 pattern repeat, three passes worked by hand") {
  using K = gm::MotionKind;
  const auto mv = lathe_moves(
      "G98 G0 X30 Z5\nG73 U3 W1 R3\nG73 P10 Q20 U1 W0.5 F90\nN10 G0 X10 Z2\nG1 Z-10 F40\n"
      "G2 X20 Z-15 R5\nN20 G1 X30\nG0 X50 Z20\nM30\n");
  // A: Z5, r15. Offsets (X radius, Z): pass 1 (3 + 0.5, 1 + 0.5), pass 2 (1.5 + 0.5, 0.5 + 0.5),
  // pass 3 (0.5, 0.5).
  REQUIRE(mv.size() == 1 + 3 * 5 + 1 + 1);
  require_end(mv[1], K::Rapid, 6.5, 18.5);  // A1
  require_end(mv[2], K::Rapid, 3.5, 8.5);   // N10 G0 shifted: B1
  require_end(mv[3], K::Line, -8.5, 8.5);
  CHECK(mv[3].feed_mm_min == Approx(90.0));  // the G73 line's F, not the profile's F40
  CHECK(mv[4].kind == K::Arc);
  require_end(mv[4], K::Arc, -13.5, 13.5);
  CHECK(mv[4].center_mm[2] == Approx(-8.5));
  CHECK(mv[4].center_mm[0] == Approx(13.5));
  require_end(mv[5], K::Line, -13.5, 18.5);  // C1
  require_end(mv[6], K::Rapid, 6.0, 17.0);   // C1 to A2
  require_end(mv[7], K::Rapid, 3.0, 7.0);
  require_end(mv[10], K::Line, -14.0, 17.0);
  require_end(mv[11], K::Rapid, 5.5, 15.5);  // A3: the allowance only
  require_end(mv[12], K::Rapid, 2.5, 5.5);
  require_end(mv[13], K::Line, -9.5, 5.5);
  require_end(mv[15], K::Line, -14.5, 15.5);
  require_end(mv[16], K::Rapid, 5.0, 15.0);  // back to A
  CHECK(mv[1].line == 3);
  require_end(mv[17], K::Rapid, 20.0, 25.0);
}

// images.elk.pl "G74 End Face Peck Drilling Cycle" (G74 R(return); G74 X(U) Z(W) P Q R F, P the
// X step and Q the peck in microns; without X, P and R: pecks of Q down to Z).
TEST_CASE("lathe-fanuc: G74 peck drilling and G75 grooving, pecks by hand") {
  using K = gm::MotionKind;
  const auto drill = lathe_moves("G98 G0 X0 Z2\nG74 R1\nG74 Z-10 Q4000 F100\nM30\n");
  // Pecks of 4 from Z2, back 1 after each: Z-2 (Z-1), Z-6 (Z-5), Z-10; out to Z2.
  REQUIRE(drill.size() == 1 + 6);
  require_end(drill[1], K::Line, -2.0, 0.0);
  CHECK(drill[1].feed_mm_min == Approx(100.0));
  require_end(drill[2], K::Rapid, -1.0, 0.0);
  require_end(drill[3], K::Line, -6.0, 0.0);
  require_end(drill[4], K::Rapid, -5.0, 0.0);
  require_end(drill[5], K::Line, -10.0, 0.0);
  require_end(drill[6], K::Rapid, 2.0, 0.0);
  // G75: pecks of 2 (radius) from r25 to r20, grooves 2 apart from Z-10 to Z-14.
  const auto groove = lathe_moves("G98 G0 X50 Z-10\nG75 R0.5\nG75 X40 Z-14 P2000 Q2000 F50\nM30\n");
  REQUIRE(groove.size() == 1 + 6 + 7 + 7 + 1);
  require_end(groove[1], K::Line, -10.0, 23.0);
  require_end(groove[2], K::Rapid, -10.0, 23.5);
  require_end(groove[3], K::Line, -10.0, 21.0);
  require_end(groove[5], K::Line, -10.0, 20.0);
  require_end(groove[6], K::Rapid, -10.0, 25.0);
  require_end(groove[7], K::Rapid, -12.0, 25.0);
  require_end(groove[8], K::Line, -12.0, 23.0);
  require_end(groove[20], K::Rapid, -14.0, 25.0);
  require_end(groove[21], K::Rapid, -10.0, 25.0);
}

// Haas's lathe manual uses the same G-code system A words: under --dialect haas a lathe reads
// G50 X Z and G50 S as under fanuc (the mill's "G50: scaling off" does not apply on a lathe).
TEST_CASE("lathe-fanuc: haas on a lathe reads G50 as the lathe's, not the end of scaling") {
  const gm::Machine m = lathe_machine();
  gm::InterpreterOptions o{&m, false};
  o.dialect = gm::Dialect::Haas;
  std::istringstream in("G0 X40 Z10\nG50 X100 Z50\nG0 X80 Z40\nM30\n");
  gm::ProgramStream s(in, "lathe.nc", o);
  std::vector<gm::Motion> mv;
  gm::Canon c;
  while (s.next(c))
    if (const auto* mo = std::get_if<gm::Motion>(&c)) mv.push_back(*mo);
  REQUIRE(mv.size() == 2);
  require_end(mv[0], gm::MotionKind::Rapid, 10.0, 20.0);  // X40 is a diameter
  require_end(mv[1], gm::MotionKind::Rapid, 0.0, 10.0);   // as the fanuc test above
}
