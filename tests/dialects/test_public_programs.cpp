// Public Fanuc/Haas programs (programs/public/, SOURCES.md): each checks clean or fails with its
// documented located error, and a few blocks of each are worked by hand from the program text.
#include <catch2/catch.hpp>

#include "interp/program.hpp"
#include "machine/machine.hpp"
#include "machine/machine_file.hpp"
#include "machine/tool_table.hpp"

#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace {

const std::string kPrograms = std::string(GMOTION_TESTS_DIR) + "/../programs/";

std::string read_file(const std::string& name) {
  std::ifstream in(kPrograms + "public/" + name, std::ios::binary);
  REQUIRE(in.good());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

gm::InterpreterOptions options(const gm::Machine& m, gm::Dialect d) {
  gm::InterpreterOptions o{&m, false};
  o.dialect = d;
  return o;
}

std::vector<gm::Diagnostic> errors_of(const std::string& text, const gm::Machine& m,
                                      gm::Dialect d) {
  std::istringstream in(text);
  std::vector<gm::Diagnostic> all, errors;
  gm::check_program_diagnostics(in, "public.nc", options(m, d), all);
  for (const gm::Diagnostic& x : all)
    if (x.severity == gm::Severity::Error) errors.push_back(x);
  return errors;
}

struct Run {
  std::vector<gm::Motion> moves;
  std::vector<gm::Dwell> dwells;
  /// The moves of source line `line`, in order.
  std::vector<gm::Motion> of(int line) const {
    std::vector<gm::Motion> out;
    for (const gm::Motion& m : moves)
      if (m.line == line) out.push_back(m);
    return out;
  }
};

Run run(const std::string& text, const gm::Machine& m, gm::Dialect d) {
  std::istringstream in(text);
  gm::ProgramStream s(in, "public.nc", options(m, d));
  Run r;
  gm::Canon c;
  while (s.next(c)) {
    if (const auto* mo = std::get_if<gm::Motion>(&c)) r.moves.push_back(*mo);
    if (const auto* dw = std::get_if<gm::Dwell>(&c)) r.dwells.push_back(*dw);
  }
  return r;
}

gm::Machine lathe() {
  return gm::load_machine_file(kPrograms + "machines/lathe.toml");
}

// A lathe move's end: Z and X as a radius (machine coordinates, mm).
void require_zx(const gm::Motion& m, gm::MotionKind kind, double z, double x_radius) {
  INFO("line " << m.line << " end Z" << m.end_mm[2] << " X(r)" << m.end_mm[0]);
  CHECK(m.kind == kind);
  CHECK(m.end_mm[2] == Approx(z).margin(1e-9));
  CHECK(m.end_mm[0] == Approx(x_radius).margin(1e-9));
}

void require_xyz(const gm::Motion& m, gm::MotionKind kind, double x, double y, double z) {
  INFO("line " << m.line << " end " << m.end_mm[0] << " " << m.end_mm[1] << " " << m.end_mm[2]);
  CHECK(m.kind == kind);
  CHECK(m.end_mm[0] == Approx(x).margin(1e-9));
  CHECK(m.end_mm[1] == Approx(y).margin(1e-9));
  CHECK(m.end_mm[2] == Approx(z).margin(1e-9));
}

// G96: spindle rpm at radius r_mm for surface speed v m/min, capped by G50 S (0: no cap).
double css_rpm(double v_m_min, double r_mm, double cap_rpm = 0.0) {
  const double rpm = v_m_min * 1000.0 / (2.0 * std::numbers::pi * r_mm);
  return cap_rpm > 0.0 && rpm > cap_rpm ? cap_rpm : rpm;
}

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at))
    text.replace(at, from.size(), to), at += to.size();
  return text;
}

}  // namespace

TEST_CASE("public programs: each checks clean or fails with its documented error") {
  const gm::Machine lt = lathe();
  const gm::Machine mill = gm::default_machine();
  CHECK(errors_of(read_file("fanuc0t_lathe_turn.nc"), lt, gm::Dialect::Fanuc).empty());
  CHECK(errors_of(read_file("fanuc_lathe_flange_macro.nc"), lt, gm::Dialect::Fanuc).empty());
  // `G42 H19`: the FANUC 0M names the cutter radius offset with H (parameter OFH), read as D19.
  CHECK(errors_of(read_file("fanuc0m_mill_slot.nc"), mill, gm::Dialect::Fanuc).empty());
  {  // LinuxCNC has no radius offset by H: its error at the H stays.
    const auto e = errors_of(read_file("fanuc0m_mill_slot.nc"), mill, gm::Dialect::LinuxCNC);
    bool h_error = false;
    for (const gm::Diagnostic& x : e)
      h_error = h_error || (x.loc.line == 10 && x.loc.column == 9 &&
                            x.message.find("H word") != std::string::npos);
    CHECK(h_error);
  }
  {  // `IF [ #5405 GE 6000 ] ...` reads 0 (a fresh machine's timers): no alarm. The built-in
     // tool 4 (a 5 mm spot drill) gouges the 2.75 mm lead-in arc under G41 at line 32; the
     // two arcs after it start where that arc did not take the tool (their radii differ).
    const auto e = errors_of(read_file("haas_thread_mill.nc"), mill, gm::Dialect::Haas);
    REQUIRE(e.size() == 3);
    CHECK(e[0].loc.line == 32);
    CHECK(e[0].loc.column == 6);
    CHECK(e[0].message.find("gouging") != std::string::npos);
    CHECK(e[1].loc.line == 33);
    CHECK(e[2].loc.line == 34);
  }
  {  // Under fanuc the Haas timers are not variables: the located error stays.
    const auto e = errors_of(read_file("haas_thread_mill.nc"), mill, gm::Dialect::Fanuc);
    REQUIRE(e.size() == 1);
    CHECK(e[0].loc.line == 7);
    CHECK(e[0].loc.column == 10);
    CHECK(e[0].message.find("#5405") != std::string::npos);
  }
}

// O0358 (FANUC 0T): G50 S0600, T0202, G96 S0450 M03, facing and turning passes, no G98/G99
// (the lathe's power-on G99: F0.3 is mm/rev). lathe.tbl: tool 2 X -1.25 Z 3.5 (radius, mm);
// tools 4 and 5 are not in it (zero offsets).
TEST_CASE("public programs: FANUC 0T turning, moves by hand") {
  const Run r = run(read_file("fanuc0t_lathe_turn.nc"), lathe(), gm::Dialect::Fanuc);
  using K = gm::MotionKind;
  // Line 10 `G01X118M08F0.3` after `X86.` and `Z0.25`: r59 - 1.25, Z0.25 + 3.5. G96 S450 at
  // r43: 450000 / (2 pi 43) = 1665.6 rpm, over G50 S600: 600 rpm x 0.3 mm/rev = 180 mm/min.
  REQUIRE(r.of(10).size() == 1);
  require_zx(r.of(10)[0], K::Line, 3.75, 57.75);
  CHECK(r.of(10)[0].mm_per_rev == Approx(0.3));
  CHECK(r.of(10)[0].feed_mm_min == Approx(0.3 * css_rpm(450.0, 43.0, 600.0)));
  CHECK(r.of(10)[0].feed_mm_min == Approx(180.0));
  // Line 13 `G01Z-51.4` at X96.: r48 - 1.25, Z-51.4 + 3.5.
  require_zx(r.of(13).at(0), K::Line, -47.9, 46.75);
  // Line 35 `G01X118M08F0.3` with T0505 (no offsets) from X97.04 Z-45: 1476 rpm capped at 600.
  require_zx(r.of(35).at(0), K::Line, -45.0, 59.0);
  CHECK(r.of(35)[0].feed_mm_min == Approx(0.3 * css_rpm(450.0, 48.52, 600.0)));
  // Line 56 `X107.91Z-1` (T0404, no offsets): the chamfer's end.
  require_zx(r.of(56).at(0), K::Line, -1.0, 53.955);
}

// O0100 (FLANGE OP.2): Macro B variables #501-#509 set at the top and used in brackets, T0101,
// U words, G96 S250 with no G50 clamp, G4 P dwells. lathe.tbl: tool 1 no offset, tool 3 X 2.0
// Z -1.5, tool 5 not in it.
TEST_CASE("public programs: Fanuc lathe flange with Macro B variables, moves by hand") {
  const Run r = run(read_file("fanuc_lathe_flange_macro.nc"), lathe(), gm::Dialect::Fanuc);
  using K = gm::MotionKind;
  // Line 20 `G1Z[#502]F0.35` at X[#501] = 350: Z-23, r175; 0.35 mm/rev at 250000/(2 pi 175).
  require_zx(r.of(20).at(0), K::Line, -23.0, 175.0);
  CHECK(r.of(20)[0].feed_mm_min == Approx(0.35 * css_rpm(250.0, 175.0)));
  // Line 27 `G1U-4.6Z[#503+.3]F0.2` from X[#501+2.] = 352, Z[#503-2.] = -7: X347.4, Z-4.7.
  require_zx(r.of(27).at(0), K::Line, -4.7, 173.7);
  CHECK(r.of(27)[0].feed_mm_min == Approx(0.2 * css_rpm(250.0, 176.0)));
  // Line 46 `G1X[#509]W-1.3F.15` from Z[#508+0.5] = -7.5: X45.15, Z-8.8 (tool 5: no offset).
  require_zx(r.of(46).at(0), K::Line, -8.8, 22.575);
  // Line 53 `G96X[#501+2.]Z[#505+50.]` under T0303 (line 52): r176 + 2, Z50 - 1.5.
  require_zx(r.of(53).at(0), K::Rapid, 48.5, 178.0);
  // Lines 62, 65, 68 `G4P200`, `G04P2000`, `G4P6000`: P without a decimal point is
  // milliseconds on a Fanuc control: 0.2 s, 2 s, 6 s, 8.2 s of dwell in all.
  REQUIRE(r.dwells.size() == 3);
  CHECK(r.dwells[0].line == 62);
  CHECK(r.dwells[0].seconds == Approx(0.2));
  CHECK(r.dwells[1].line == 65);
  CHECK(r.dwells[1].seconds == Approx(2.0));
  CHECK(r.dwells[2].line == 68);
  CHECK(r.dwells[2].seconds == Approx(6.0));
  CHECK(r.dwells[0].seconds + r.dwells[1].seconds + r.dwells[2].seconds == Approx(8.2));
}

// :0097 (FANUC 0M) as published: `G42 H19` is the radius of offset 19, as `G42 D19` (tool 19
// is not in the table: radius 0, the path as programmed). Built-in tool table: tool 3 Z 45;
// tool 5 not in it; G55 is zero.
TEST_CASE("public programs: FANUC 0M slot, H19 read as D19, moves by hand") {
  const std::string text = read_file("fanuc0m_mill_slot.nc");
  const gm::Machine mill = gm::default_machine();
  REQUIRE(errors_of(text, mill, gm::Dialect::Fanuc).empty());
  const Run r = run(text, mill, gm::Dialect::Fanuc);
  {  // The same moves as the program written with D19.
    const Run d = run(replace_all(text, "G42 H19", "G42 D19"), mill, gm::Dialect::Fanuc);
    REQUIRE(d.moves.size() == r.moves.size());
    for (std::size_t i = 0; i < r.moves.size(); ++i) CHECK(d.moves[i].end_mm == r.moves[i].end_mm);
  }
  using K = gm::MotionKind;
  // Line 7 `N20 G43 H3 Z39. M8` at X2. Y0: Z39 + 45.
  require_xyz(r.of(7).at(0), K::Rapid, 2.0, 0.0, 84.0);
  // Line 8 `N30 G1 Z29.88 F39`.
  require_xyz(r.of(8).at(0), K::Line, 2.0, 0.0, 74.88);
  CHECK(r.of(8)[0].feed_mm_min == Approx(39.0));
  // Line 14 `N90 G2 X-114. Y10. R10. F39` from (-114, -10): a chord of 20 = 2 R, the centre
  // is its midpoint (-114, 0).
  const gm::Motion arc = r.of(14).at(0);
  require_xyz(arc, K::Arc, -114.0, 10.0, 74.88);
  CHECK(arc.center_mm[0] == Approx(-114.0));
  CHECK(arc.center_mm[1] == Approx(0.0).margin(1e-9));
  CHECK_FALSE(arc.ccw);
  // Line 22 `N160 G1 Z42.46 F25` under G43 H5 (tool 5: length 0) at X-910. Y0.
  require_xyz(r.of(22).at(0), K::Line, -910.0, 0.0, 42.46);
}

// O00094 (HAAS) as published: its two tool-life checks (`IF [#5405 GE 6000] THEN #3000=15`)
// read a fresh machine's feed timers (0 s: no alarm); a tool table whose thread mill (T4) has a
// 1 mm diameter (the built-in 5 mm spot drill gouges the 2.75 mm lead-in arc under G41, a
// located error at line 32). G10 L2 P1 Y-254.65 Z-689. is G54.
TEST_CASE("public programs: Haas thread milling, moves by hand") {
  const std::string text = read_file("haas_thread_mill.nc");
  gm::Machine mill = gm::default_machine();
  std::istringstream tools("T3 P3 Z45 D20\nT4 P4 Z70 D1\n");
  mill.tool_table = gm::read_tool_table(tools, "<test>");
  REQUIRE(errors_of(text, mill, gm::Dialect::Haas).empty());
  const Run r = run(text, mill, gm::Dialect::Haas);
  using K = gm::MotionKind;
  const double x0 = -269.39, y0 = -254.65, z0 = -689.0;
  // Line 12 `N90 G81 G98 Z-15. R5. F412` at X5.25 Y0. under G43 H05 (tool 5: length 0): rapid
  // to R, feed to Z-15, back to the initial level Z50 (G98).
  const auto drill = r.of(12);
  REQUIRE(drill.size() == 3);
  require_xyz(drill[0], K::Rapid, x0 + 5.25, y0, z0 + 5.0);
  require_xyz(drill[1], K::Line, x0 + 5.25, y0, z0 - 15.0);
  CHECK(drill[1].feed_mm_min == Approx(412.0));
  require_xyz(drill[2], K::Rapid, x0 + 5.25, y0, z0 + 50.0);
  // Line 13 `N100 G00 G80 Z100. M89`: G00 and G80 in one block (two groups on a Fanuc/Haas).
  require_xyz(r.of(13).at(0), K::Rapid, x0 + 5.25, y0, z0 + 100.0);
  // Line 32 `N290 G03 X5.5 Y0. I0. J2.75 Z-11.813 F80` under G41 D04 (radius 0.5), tool 4 Z70:
  // the tool runs inside the arc about (2.75, 0), 0.5 short of X5.5.
  const gm::Motion helix = r.of(32).at(0);
  require_xyz(helix, K::Arc, x0 + 5.0, y0, z0 + 70.0 - 11.813);
  CHECK(helix.center_mm[0] == Approx(x0 + 2.75));
  CHECK(helix.ccw);
  // Line 38 `N350 G53 X-508. Y0.`: machine coordinates.
  require_xyz(r.of(38).at(0), K::Rapid, -508.0, 0.0, 0.0);
}

// What the programs revealed, each on the smallest program.
TEST_CASE("public programs: a Fanuc lathe starts in G99, G00 G80 is one block") {
  SECTION("F without G98/G99 on a lathe is per revolution") {
    const std::string p = "G97 S500 M3\nG0 X40 Z2\nG1 Z-10 F0.2\nG98 G1 Z-20 F100\nM30\n";
    const Run r = run(p, lathe(), gm::Dialect::Fanuc);
    REQUIRE(r.of(3).size() == 1);
    CHECK(r.of(3)[0].mm_per_rev == Approx(0.2));
    CHECK(r.of(3)[0].feed_mm_min == Approx(0.2 * 500.0));
    CHECK(r.of(4).at(0).mm_per_rev == 0.0);
    CHECK(r.of(4)[0].feed_mm_min == Approx(100.0));
  }
  SECTION("G00 G80 and G80 G01 with axis words") {
    const std::string p =
        "G0 X0 Y0 Z10\nG99 G81 X5 Y0 Z-2 R1 F100\nG00 G80 Z20\nX10\nG81 X5 Z-2 R1\n"
        "G80 G01 Z5 F50\nM30\n";
    const gm::Machine mill = gm::default_machine();
    REQUIRE(errors_of(p, mill, gm::Dialect::Fanuc).empty());
    const Run r = run(p, mill, gm::Dialect::Fanuc);
    // Tool 0: no length. Line 3 a rapid up to Z20, line 4 a rapid to X10 (no hole drilled).
    REQUIRE(r.of(3).size() == 1);
    require_xyz(r.of(3)[0], gm::MotionKind::Rapid, 5.0, 0.0, 20.0);
    REQUIRE(r.of(4).size() == 1);
    require_xyz(r.of(4)[0], gm::MotionKind::Rapid, 10.0, 0.0, 20.0);
    // Line 6: fed up from the R plane (G99 left the drill at R1) to Z5 at F50.
    REQUIRE(r.of(6).size() == 1);
    require_xyz(r.of(6)[0], gm::MotionKind::Line, 5.0, 0.0, 5.0);
    CHECK(r.of(6)[0].feed_mm_min == Approx(50.0));
  }
}

// Fanuc's and Haas's G04: P without a decimal point in milliseconds, X (U on a lathe) in seconds.
TEST_CASE("public programs: G04 P in milliseconds, X and U in seconds") {
  const gm::Machine mill = gm::default_machine();
  const std::string p = "#1 = 3000\nG04 P2000\nG4 P250\nG04 X1.5\nG04 X2\nG4 P#1\nM30\n";
  for (gm::Dialect d : {gm::Dialect::Fanuc, gm::Dialect::Haas}) {
    INFO(gm::dialect_name(d));
    REQUIRE(errors_of(p, mill, d).empty());
    const Run r = run(p, mill, d);
    // `P#1`: a value from a variable has no written point, so milliseconds (3000 ms).
    REQUIRE(r.dwells.size() == 5);
    CHECK(r.dwells[0].seconds == Approx(2.0));
    CHECK(r.dwells[1].seconds == Approx(0.25));
    CHECK(r.dwells[2].seconds == Approx(1.5));
    CHECK(r.dwells[3].seconds == Approx(2.0));
    CHECK(r.dwells[4].seconds == Approx(3.0));
  }
  {  // LinuxCNC: P in seconds, unchanged.
    const Run r = run("G4 P2000\nG4 P2.5\nM2\n", mill, gm::Dialect::LinuxCNC);
    REQUIRE(r.dwells.size() == 2);
    CHECK(r.dwells[0].seconds == Approx(2000.0));
    CHECK(r.dwells[1].seconds == Approx(2.5));
  }
  {  // A point in P: Haas seconds; Fanuc refuses it (the manual: no decimal point in P).
    const std::string q = "G04 P2.5\nG04 P.5\nM30\n";
    const Run haas = run(q, mill, gm::Dialect::Haas);
    REQUIRE(haas.dwells.size() == 2);
    CHECK(haas.dwells[0].seconds == Approx(2.5));
    CHECK(haas.dwells[1].seconds == Approx(0.5));
    const auto e = errors_of(q, mill, gm::Dialect::Fanuc);
    REQUIRE(e.size() == 2);
    CHECK(e[0].loc.line == 1);
    CHECK(e[0].loc.column == 5);
    CHECK(e[0].message.find("milliseconds") != std::string::npos);
  }
  {  // P and X together: one error.
    const auto e = errors_of("G04 P100 X1.\nM30\n", mill, gm::Dialect::Fanuc);
    REQUIRE(e.size() == 1);
    CHECK(e[0].loc.column == 10);
  }
  {  // A lathe: U is seconds too (not an incremental X), X not a diameter.
    const Run r = run("G04 U1.5\nG04 X3.\nG4 P500\nM30\n", lathe(), gm::Dialect::Fanuc);
    REQUIRE(r.dwells.size() == 3);
    CHECK(r.dwells[0].seconds == Approx(1.5));
    CHECK(r.dwells[1].seconds == Approx(3.0));
    CHECK(r.dwells[2].seconds == Approx(0.5));
    CHECK(r.moves.empty());
  }
}

// The drilling cycles' dwell P as G04's: milliseconds without a decimal point (zanotowane.pl
// "G81 Drilling Spot Boring": P the dwell at the bottom, "see the G04 code"; cnclearning.com
// "G82": P in milliseconds on Fanuc controls), Haas's P with a point in seconds, Fanuc's refused.
TEST_CASE("public programs: drilling cycles' dwell P in milliseconds under fanuc and haas") {
  const gm::Machine mill = gm::default_machine();
  // G99 (the start): each hole from R2 down to Z-5 and back to R2. Line 3 changes the dwell for
  // its hole and the next (P is sticky), line 5 is a G89 of its own.
  const std::string p =
      "G0 X0 Y0 Z10\nG82 X10 Y10 Z-5 R2 P1500 F100\nX20 P500\nX30\nG89 X40 Z-3 R2 P250\n"
      "G80\nM30\n";
  for (gm::Dialect d : {gm::Dialect::Fanuc, gm::Dialect::Haas}) {
    INFO(gm::dialect_name(d));
    REQUIRE(errors_of(p, mill, d).empty());
    const Run r = run(p, mill, d);
    REQUIRE(r.dwells.size() == 4);
    CHECK(r.dwells[0].line == 2);
    CHECK(r.dwells[0].seconds == Approx(1.5));
    CHECK(r.dwells[1].line == 3);
    CHECK(r.dwells[1].seconds == Approx(0.5));
    CHECK(r.dwells[2].line == 4);
    CHECK(r.dwells[2].seconds == Approx(0.5));
    CHECK(r.dwells[3].line == 5);
    CHECK(r.dwells[3].seconds == Approx(0.25));
    // Line 2: over to (10, 10) at Z10, down to R2, fed to Z-5 at F100, back to R2 (G99).
    const auto hole = r.of(2);
    REQUIRE(hole.size() == 4);
    require_xyz(hole[0], gm::MotionKind::Rapid, 10.0, 10.0, 10.0);
    require_xyz(hole[1], gm::MotionKind::Rapid, 10.0, 10.0, 2.0);
    require_xyz(hole[2], gm::MotionKind::Line, 10.0, 10.0, -5.0);
    CHECK(hole[2].feed_mm_min == Approx(100.0));
    require_xyz(hole[3], gm::MotionKind::Rapid, 10.0, 10.0, 2.0);
    // Line 5 (G89): fed back out to R2 after its dwell.
    const auto bore = r.of(5);
    REQUIRE(bore.size() == 3);
    require_xyz(bore[1], gm::MotionKind::Line, 40.0, 10.0, -3.0);
    require_xyz(bore[2], gm::MotionKind::Line, 40.0, 10.0, 2.0);
  }
  {  // LinuxCNC: seconds, unchanged.
    const Run r = run(p, mill, gm::Dialect::LinuxCNC);
    REQUIRE(r.dwells.size() == 4);
    CHECK(r.dwells[0].seconds == Approx(1500.0));
    CHECK(r.dwells[1].seconds == Approx(500.0));
    CHECK(r.dwells[2].seconds == Approx(500.0));
    CHECK(r.dwells[3].seconds == Approx(250.0));
  }
  {  // A point in P: Haas seconds; Fanuc refuses it at the P.
    const std::string q = "G0 X0 Y0 Z10\nG82 X10 Y10 Z-5 R2 P1.5 F100\nG80\nM30\n";
    const Run haas = run(q, mill, gm::Dialect::Haas);
    REQUIRE(haas.dwells.size() == 1);
    CHECK(haas.dwells[0].seconds == Approx(1.5));
    const auto e = errors_of(q, mill, gm::Dialect::Fanuc);
    REQUIRE(e.size() == 1);
    CHECK(e[0].loc.line == 2);
    CHECK(e[0].loc.column == 20);
    CHECK(e[0].message ==
          "G82 P1.5: Fanuc's P is milliseconds without a decimal point (write P1500)");
  }
  {  // G84 (tapping, M3): its dwell at the bottom between feeding in and the reversed feed out.
    const std::string q = "S500 M3\nG0 X0 Y0 Z10\nG84 X5 Y5 Z-5 R2 P250 F100\nG80\nM30\n";
    const Run r = run(q, mill, gm::Dialect::Fanuc);
    REQUIRE(r.dwells.size() == 1);
    CHECK(r.dwells[0].line == 3);
    CHECK(r.dwells[0].seconds == Approx(0.25));
  }
  {  // Under the cycle, a P another code takes is that code's: `G10 L2 P1 X5` sets G54's X
     // (P1 is not 0.001), the next hole is at X20 + 5.
    const std::string q =
        "G0 X0 Y0 Z10\nG82 X10 Y10 Z-5 R2 P1000 F100\nG10 L2 P1 X5\nX20\n"
        "G80\nM30\n";
    REQUIRE(errors_of(q, mill, gm::Dialect::Fanuc).empty());
    const Run r = run(q, mill, gm::Dialect::Fanuc);
    CHECK(r.of(3).empty());
    REQUIRE(r.dwells.size() == 2);
    CHECK(r.dwells[1].line == 4);
    CHECK(r.dwells[1].seconds == Approx(1.0));
    require_xyz(r.of(4).at(1), gm::MotionKind::Line, 25.0, 10.0, -5.0);
  }
}

// `G41/G42 H` on a Fanuc mill: the cutter radius offset numbered by H (FANUC Series 16/18-MC
// B-62764EN/01, II-15.5, note 2: "Cutter compensation C can be specified by H code with
// parameter OFH (No. 5001 #2) set to 1"), the radius of the tool table's entry as D gives it.
TEST_CASE("public programs: G42 H is the cutter radius offset under fanuc and haas") {
  gm::Machine mill = gm::default_machine();
  std::istringstream tools("T3 P3 Z45 D20\nT19 P19 D10\n");
  mill.tool_table = gm::read_tool_table(tools, "<test>");
  // Along +X with the tool right of the path (G42): 5 mm (D10 / 2) below it, on Y-5.
  const std::string p = "G0 X0 Y0 Z0\nG42 H19 G1 X10 F100\nX50\nX80\nG40 G0 Y-20\nM30\n";
  for (gm::Dialect d : {gm::Dialect::Fanuc, gm::Dialect::Haas}) {
    INFO(gm::dialect_name(d));
    REQUIRE(errors_of(p, mill, d).empty());
    const Run r = run(p, mill, d);
    require_xyz(r.of(3).at(0), gm::MotionKind::Line, 50.0, -5.0, 0.0);
    const Run with_d = run(replace_all(p, "H19", "D19"), mill, d);
    REQUIRE(with_d.moves.size() == r.moves.size());
    for (std::size_t i = 0; i < r.moves.size(); ++i)
      CHECK(with_d.moves[i].end_mm == r.moves[i].end_mm);
  }
  {  // A D in the block: the D is the offset, the H stays LinuxCNC's word (its error, at the H).
    const auto e =
        errors_of("G0 X0 Y0 Z0\nG42 D19 H3 G1 X10 F100\nM30\n", mill, gm::Dialect::Fanuc);
    REQUIRE(e.size() == 1);
    CHECK(e[0].loc.line == 2);
    CHECK(e[0].loc.column == 9);
    CHECK(e[0].message.find("H word") != std::string::npos);
  }
  {  // LinuxCNC: no radius offset by H.
    const auto e = errors_of(p, mill, gm::Dialect::LinuxCNC);
    REQUIRE(e.size() == 1);
    CHECK(e[0].loc.line == 2);
    CHECK(e[0].message.find("H word") != std::string::npos);
  }
}
