// Public CAM programs (programs/public/cam/, SOURCES.md): each checks clean and runs, holds G64
// P0.01 on every sample, and a few of its moves are worked by hand from the program text.
#include <catch2/catch.hpp>

#include "interp/program.hpp"
#include "machine/machine.hpp"
#include "pipeline/run.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

const std::string kCam = std::string(GMOTION_TESTS_DIR) + "/../programs/public/cam/";
constexpr double kInch_mm = 25.4;

std::string read_file(const std::string& name) {
  std::ifstream in(kCam + name, std::ios::binary);
  REQUIRE(in.good());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<gm::Diagnostic> errors_of(const std::string& text, const gm::Machine& m) {
  std::istringstream in(text);
  std::vector<gm::Diagnostic> all, errors;
  gm::check_program_diagnostics(in, "cam.nc", gm::InterpreterOptions{&m, false}, all);
  for (const gm::Diagnostic& x : all)
    if (x.severity == gm::Severity::Error) errors.push_back(x);
  return errors;
}

std::vector<gm::Motion> moves_of(const std::string& text, const gm::Machine& m) {
  std::istringstream in(text);
  gm::ProgramStream s(in, "cam.nc", gm::InterpreterOptions{&m, false});
  std::vector<gm::Motion> out;
  gm::Canon c;
  while (s.next(c))
    if (const auto* mo = std::get_if<gm::Motion>(&c)) out.push_back(*mo);
  return out;
}

/// The first move of source line `line`.
gm::Motion move_at(const std::vector<gm::Motion>& moves, int line) {
  for (const gm::Motion& m : moves)
    if (m.line == line) return m;
  FAIL("no move on line " << line);
  return {};
}

int arcs_in(const std::vector<gm::Motion>& moves) {
  int n = 0;
  for (const gm::Motion& m : moves) n += m.kind == gm::MotionKind::Arc;
  return n;
}

void require_point(const gm::AxisVec& p, double x, double y, double z) {
  INFO("point " << p[0] << " " << p[1] << " " << p[2]);
  CHECK(p[0] == Approx(x).margin(1e-9));
  CHECK(p[1] == Approx(y).margin(1e-9));
  CHECK(p[2] == Approx(z).margin(1e-9));
}

/// `text` with `mode` inserted as its own line before (1-based) line `before`.
std::string with_line(const std::string& text, int before, const std::string& mode) {
  std::size_t at = 0;
  for (int l = 1; l < before; ++l) at = text.find('\n', at) + 1;
  return text.substr(0, at) + mode + "\n" + text.substr(at);
}

struct Ran {
  gm::RunStatus status = gm::RunStatus::Working;
  gm::AxisBlu end_blu = gm::AxisBlu::Zero();
  gm::ToleranceCheck::Worst cutting, rapids;
  std::int64_t samples = 0;
};

Ran run(const std::string& text, const gm::Machine& m) {
  std::istringstream in(text);
  gm::RunOptions o;
  o.config.machine = m;
  o.config.servo = false;
  o.program_name = "cam.nc";
  gm::Run run(std::move(o), in, gm::InterpreterOptions{&m, false});
  Ran r;
  while ((r.status = run.advance()) == gm::RunStatus::Working) {
  }
  r.end_blu = run.pipeline().program_end_blu();
  r.cutting = run.tolerance().cutting();
  r.rapids = run.tolerance().rapids();
  r.samples = run.summary().samples;
  return r;
}

struct Program {
  const char* file;
  int mode_before;  ///< the line the inserted `G64 P` goes before (the first axis word's)
  bool inch;        ///< G20 in the preamble: P is read in inches
};

const std::vector<Program> kPrograms = {
    {"fusion-bore-tests.nc", 15, false},
    {"fusion-tab-contour.nc", 15, false},
    {"cambam-engrave.nc", 5, true},
    {"sketchucam-rword.gcode", 15, true},
};

gm::AxisBlu to_blu(const gm::AxisVec& mm, const gm::Machine& m) {
  gm::AxisBlu b = gm::AxisBlu::Zero();
  for (int a = 0; a < 3; ++a) b[a] = std::llround(mm[a] / m.axes[a].blu_mm);
  return b;
}

}  // namespace

TEST_CASE("public CAM programs: each checks clean with its arcs counted by hand") {
  const gm::Machine m = gm::default_machine();
  // G2/G3 moves counted from the text: lines with an axis word while the modal motion is G2 or
  // G3 (Fusion writes the G only when it changes): 4 G2 (G18, XZ) + 172 G3 in the bores, 21 G2
  // + 9 G3 (6 of them G19, YZ) in the tab contour, 117 G2 + 118 G3 in the CamBam engraving, 168
  // G3 (R words) in SketchUcam's passes.
  const int arcs[] = {176, 30, 235, 168};
  for (std::size_t k = 0; k < kPrograms.size(); ++k) {
    INFO(kPrograms[k].file);
    const std::string text = read_file(kPrograms[k].file);
    CHECK(errors_of(text, m).empty());
    CHECK(arcs_in(moves_of(text, m)) == arcs[k]);
  }
}

// Fusion 360 (led_floor 1102): `G0 X14.925 Y14.73` (Z stays 0), `Z0.27` by G1, then a G18 lead-in
// `G2 X15.195 Z0 I0.27 K0` (centre = start + (I, K) in X and Z), `G1 X15.33`, and the first G17
// helix turn `G3 X15.6 Y15 I0 J0.27` then `X14.4 Y15 Z-0.25 I-0.6 J0` (modal G3).
TEST_CASE("public CAM programs: Fusion 360 bores worked by hand") {
  const auto mv = moves_of(read_file("fusion-bore-tests.nc"), gm::default_machine());
  const gm::Motion g0 = move_at(mv, 15);
  CHECK(g0.kind == gm::MotionKind::Rapid);
  require_point(g0.end_mm, 14.925, 14.73, 0.0);
  const gm::Motion lead = move_at(mv, 19);
  REQUIRE(lead.kind == gm::MotionKind::Arc);
  CHECK(lead.plane == gm::Plane::XZ);
  CHECK_FALSE(lead.ccw);
  require_point(lead.start_mm, 14.925, 14.73, 0.27);
  require_point(lead.center_mm, 14.925 + 0.27, 14.73, 0.27 + 0.0);
  require_point(lead.end_mm, 15.195, 14.73, 0.0);
  const gm::Motion quarter = move_at(mv, 21);
  REQUIRE(quarter.kind == gm::MotionKind::Arc);
  CHECK(quarter.ccw);
  require_point(quarter.center_mm, 15.33 + 0.0, 14.73 + 0.27, 0.0);
  require_point(quarter.end_mm, 15.6, 15.0, 0.0);
  const gm::Motion helix = move_at(mv, 22);
  REQUIRE(helix.kind == gm::MotionKind::Arc);
  CHECK(helix.ccw);
  require_point(helix.center_mm, 15.6 - 0.6, 15.0, 0.0);
  require_point(helix.end_mm, 14.4, 15.0, -0.25);
}

// Fusion 360 (led_floor 1011): after `Z-2.05` at X12.2 Y-1.6, the G19 lead-in `G3 Y-1.4 Z-2.25
// J0.2 K0` (centre = start + (J, K) in Y and Z), `G1 Y-1.2`, then `G17 G3 X12 Y-1 I-0.2 J0` and
// `G2 X11 Y0 I0 J1`.
TEST_CASE("public CAM programs: Fusion 360 tab contour worked by hand") {
  const auto mv = moves_of(read_file("fusion-tab-contour.nc"), gm::default_machine());
  require_point(move_at(mv, 15).end_mm, 12.2, -1.6, 0.0);
  const gm::Motion lead = move_at(mv, 20);
  REQUIRE(lead.kind == gm::MotionKind::Arc);
  CHECK(lead.plane == gm::Plane::YZ);
  CHECK(lead.ccw);
  require_point(lead.start_mm, 12.2, -1.6, -2.05);
  require_point(lead.center_mm, 12.2, -1.6 + 0.2, -2.05 + 0.0);
  require_point(lead.end_mm, 12.2, -1.4, -2.25);
  const gm::Motion turn = move_at(mv, 22);
  CHECK(turn.plane == gm::Plane::XY);
  require_point(turn.center_mm, 12.2 - 0.2, -1.2, -2.25);
  const gm::Motion corner = move_at(mv, 23);
  CHECK_FALSE(corner.ccw);
  require_point(corner.center_mm, 12.0 + 0.0, -1.0 + 1.0, -2.25);
  require_point(corner.end_mm, 11.0, 0.0, -2.25);
}

// CamBam (inches, G20): `G0 Y-0.0451` at Z0.125, `G1 F10.0 Z-0.001`, `G1 F60.0 X-2.8845
// Y-0.035`, then `G3 X-2.8723 Y-0.0943 I0.3244 J0.0363`: centre (-2.8845 + 0.3244, -0.035 +
// 0.0363) in, times 25.4.
TEST_CASE("public CAM programs: CamBam engraving in inches worked by hand") {
  const auto mv = moves_of(read_file("cambam-engrave.nc"), gm::default_machine());
  const gm::Motion g0 = move_at(mv, 11);
  CHECK(g0.kind == gm::MotionKind::Rapid);
  require_point(g0.end_mm, -3.0 * kInch_mm, -0.0451 * kInch_mm, 0.125 * kInch_mm);
  CHECK(move_at(mv, 13).feed_mm_min == Approx(60.0 * kInch_mm));
  const gm::Motion arc = move_at(mv, 14);
  REQUIRE(arc.kind == gm::MotionKind::Arc);
  CHECK(arc.ccw);
  require_point(arc.center_mm, (-2.8845 + 0.3244) * kInch_mm, (-0.035 + 0.0363) * kInch_mm,
                -0.001 * kInch_mm);
  require_point(arc.end_mm, -2.8723 * kInch_mm, -0.0943 * kInch_mm, -0.001 * kInch_mm);
}

// SketchUcam (inches, R words): `G17 G0 Z0.2500`, `X0.3645 Y0.3782`, `G1 Z-0.1250 F100`, `X3.4311`,
// then `G17 G3 X3.7021 Y0.4139 Z-0.1250 R1.0625`. R > 0, G3: the centre lies left of the chord from
// A (3.4311, 0.3782) to B (3.7021, 0.4139), sqrt(R^2 - (c/2)^2) from its midpoint.
TEST_CASE("public CAM programs: SketchUcam R-word arcs worked by hand") {
  const auto mv = moves_of(read_file("sketchucam-rword.gcode"), gm::default_machine());
  require_point(move_at(mv, 17).end_mm, 0.3645 * kInch_mm, 0.3782 * kInch_mm, 0.25 * kInch_mm);
  CHECK(move_at(mv, 18).feed_mm_min == Approx(100.0 * kInch_mm));
  const gm::Motion arc = move_at(mv, 20);
  REQUIRE(arc.kind == gm::MotionKind::Arc);
  CHECK(arc.ccw);
  const double ax = 3.4311, ay = 0.3782, bx = 3.7021, by = 0.4139, r = 1.0625;
  const double cx = bx - ax, cy = by - ay, chord = std::hypot(cx, cy);
  const double h = std::sqrt(r * r - chord * chord / 4.0);   // midpoint to centre
  const double centre_x = (ax + bx) / 2.0 - h * cy / chord;  // left normal of (cx, cy)
  const double centre_y = (ay + by) / 2.0 + h * cx / chord;
  CHECK(centre_x == Approx(3.42897).margin(1e-4));  // the profile's centre, near X3.429 Y1.4407
  CHECK(centre_y == Approx(1.44066).margin(1e-4));
  // The interpreter carries the R arc's centre to within its end point's rounding (0.1 µm).
  CHECK(arc.center_mm[0] == Approx(centre_x * kInch_mm).margin(1e-6));
  CHECK(arc.center_mm[1] == Approx(centre_y * kInch_mm).margin(1e-6));
  require_point(arc.end_mm, 3.7021 * kInch_mm, 0.4139 * kInch_mm, -0.125 * kInch_mm);
}

// Each runs through the whole pipeline (servo off) as published and at G64 P0.01 (mm; written
// `P[0.01/25.4]` in the inch programs) inserted before its first axis word: it ends exactly on
// its last programmed point, and at P0.01 no sample leaves the tolerance.
TEST_CASE("public CAM programs: each runs and holds G64 P0.01 on every sample") {
  const gm::Machine m = gm::default_machine();
  for (const Program& p : kPrograms) {
    INFO(p.file);
    const std::string text = read_file(p.file);
    const auto mv = moves_of(text, m);
    REQUIRE_FALSE(mv.empty());
    const gm::AxisBlu last = to_blu(mv.back().end_mm, m);
    const Ran as_published = run(text, m);
    CHECK(as_published.status == gm::RunStatus::Finished);
    CHECK(as_published.end_blu == last);
    const Ran p01 =
        run(with_line(text, p.mode_before, p.inch ? "G64 P[0.01/25.4]" : "G64 P0.01"), m);
    CHECK(p01.status == gm::RunStatus::Finished);
    CHECK(p01.end_blu == last);
    CHECK(p01.cutting.samples > 0);
    CHECK(p01.cutting.over == 0);
    CHECK(p01.rapids.over == 0);
    CHECK(p01.cutting.tol_mm == Approx(0.01).margin(1e-12));
    CHECK(p01.cutting.err_mm <= 0.01);
    CHECK(p01.samples > as_published.samples);  // P0.01 is slower than the programs' own G64
  }
}
