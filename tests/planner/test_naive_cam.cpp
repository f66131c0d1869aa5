// G64 Q: nearly collinear G1 runs merged into one line within Q of every original vertex, end
// points exact, and a CAM polyline faster than without Q (docs/tolerance.md).
#include "accdec/taps.hpp"
#include "interp/program.hpp"
#include "machine/machine.hpp"
#include "measure/tolerance_check.hpp"
#include "pipeline/pipeline.hpp"
#include "planner/filter_moments.hpp"
#include "planner/naive_cam.hpp"
#include "planner/tolerance_planner.hpp"
#include "support/sample_stepper.hpp"
#include "support/tolerance_reference.hpp"

#include <fmt/format.h>
#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace {

std::vector<gm::Motion> merged_moves(const std::string& text, const gm::Machine& m) {
  std::istringstream in(text);
  gm::InterpreterOptions opts;
  opts.machine = &m;
  gm::ProgramStream stream(in, "q.nc", opts);
  gm::NaiveCamMerger merger(stream);
  std::vector<gm::Motion> out;
  gm::Canon c;
  while (merger.next(c))
    if (const auto* mo = std::get_if<gm::Motion>(&c)) out.push_back(*mo);
  return out;
}

// Distance from p to the segment a–b in XY (the test paths are planar).
double q_seg_dist(double px, double py, double ax, double ay, double bx, double by) {
  const double dx = bx - ax, dy = by - ay, l2 = dx * dx + dy * dy;
  double t = l2 > 0 ? ((px - ax) * dx + (py - ay) * dy) / l2 : 0.0;
  t = std::max(0.0, std::min(1.0, t));
  return std::hypot(px - ax - t * dx, py - ay - t * dy);
}

// A CAM-style polyline (after a rapid from the origin): `n` chords of 0.02 mm around a circle of
// radius 10 mm (chord sag 5·10⁻⁶ mm) with a radial wobble of ±`wobble` mm every 0.5 mm, ending with
// a 90° corner.
std::string polyline(int n, double wobble, const std::string& g64,
                     std::vector<std::pair<double, double>>* pts) {
  std::string t = fmt::format("G21 G90 G17 {}\nG0 X10 Y0\nG1 F3000\n", g64);
  *pts = {{0.0, 0.0}, {10.0, 0.0}};  // the rapid from the origin, then the polyline
  for (int k = 1; k <= n; ++k) {
    const double s = 0.02 * k, a = s / 10.0;
    const double r = 10.0 + wobble * std::sin(s * 2 * 3.141592653589793 / 0.5);
    const double x = std::round(r * std::cos(a) * 1e5) / 1e5,
                 y = std::round(r * std::sin(a) * 1e5) / 1e5;
    t += fmt::format("X{:.5f} Y{:.5f}\n", x, y);
    pts->emplace_back(x, y);
  }
  const auto [lx, ly] = pts->back();
  t += fmt::format("X{:.5f} Y{:.5f}\nM2\n", lx - 5.0, ly);  // a corner after the run
  pts->emplace_back(lx - 5.0, ly);
  return t;
}

}  // namespace

TEST_CASE("G64 Q: hand-worked runs, each vertex within Q of its merged line, ends exact") {
  const gm::Machine m;
  // (1, 0.006) is 0.006 from (0,0)–(2,0): merged. Extending to (3, 0.02) would leave (2, 0)
  // 2·0.02/√(9 + 0.0004) = 0.01333 from the line, more than Q: a new run starts at (2, 0).
  // A feed change, a rapid and an arc end runs; without Q nothing is merged.
  const auto mv = merged_moves(
      "G21 G90 G64 P0.01 Q0.01\nG1 X1 Y0.006 F1000\nX2 Y0\nX3 Y0.02\nX4 Y0.02 F900\n"
      "G0 X5\nG1 X6 F900\nG2 X8 Y0.02 I1 J0\nG1 X9\nX10\nM2\n",
      m);
  REQUIRE(mv.size() == 7);
  CHECK(mv[0].end_mm[0] == 2.0);
  CHECK(mv[0].end_mm[1] == 0.0);
  CHECK(mv[0].line == 2);
  CHECK(mv[1].start_mm[0] == 2.0);
  CHECK(mv[1].end_mm[0] == 3.0);
  CHECK(mv[1].end_mm[1] == Approx(0.02).margin(1e-12));
  CHECK(mv[2].feed_mm_min == 900);  // the feed changed: not merged with the move before
  CHECK(mv[3].kind == gm::MotionKind::Rapid);
  CHECK(mv[5].kind == gm::MotionKind::Arc);
  CHECK(mv[6].start_mm[0] == 8.0);  // X9 and X10 collinear: one move
  CHECK(mv[6].end_mm[0] == 10.0);
  CHECK(mv[6].line == 9);
  const auto plain =
      merged_moves("G21 G90 G64 P0.01\nG1 X1 Y0.006 F1000\nX2 Y0\nX3 Y0.02\nG1 X4\nX5\nM2\n", m);
  CHECK(plain.size() == 5);
}

TEST_CASE(
    "G64 P0.01 Q0.01 on a CAM polyline: merged within Q, the table within P + Q of the "
    "program, faster than P alone") {
  const gm::Machine m;
  std::vector<std::pair<double, double>> pts;
  struct Result {
    double cycle_s = 0, worst_to_program_mm = 0;
    std::size_t moves_out = 0;
    bool exceeded = true, end_exact = false;
  };
  auto run = [&](const std::string& g64) {
    const std::string text = polyline(1500, 0.003, g64, &pts);
    std::istringstream in(text);
    gm::InterpreterOptions opts;
    opts.machine = &m;
    gm::ProgramStream stream(in, "poly.nc", opts);
    const gm::FilterMoments fm(gm::design_taps(m.profile, m.tau_s, m.period_s), m.period_s);
    gm::PlannerConfig pc;
    pc.max_override = m.max_override;
    pc.rapid_mm_min = m.rapid_mm_min;
    pc.rounding_mm = m.xyz_blu_mm().norm();
    gm::TolerancePlanner planner(fm, pc, stream);
    gm::RunConfig cfg;
    cfg.machine = m;
    cfg.servo = false;
    gmtest::SampleStepper p(cfg, planner);
    gmtest::ToleranceReference check(m.contour_blu_mm());
    gm::SampleRecord rec;
    Result r;
    std::size_t seg = 0;  // the program's polyline advances monotonically: search near `seg`
    while (p.step({}, rec) == gm::PipelineStatus::Working) {
      check.add(rec, p.started_motion());
      const double x = rec.table_blu[0] * m.axes[0].blu_mm, y = rec.table_blu[1] * m.axes[1].blu_mm;
      double best = 1e9;
      const std::size_t lo = seg > 200 ? seg - 200 : 0, hi = std::min(pts.size() - 1, seg + 200);
      std::size_t at = seg;
      for (std::size_t i = lo; i < hi; ++i) {
        const double d =
            q_seg_dist(x, y, pts[i].first, pts[i].second, pts[i + 1].first, pts[i + 1].second);
        if (d < best) best = d, at = i;
      }
      seg = at;
      r.worst_to_program_mm = std::max(r.worst_to_program_mm, best);
    }
    r.cycle_s = rec.t_s + m.period_s;
    r.exceeded = check.exceeded();
    r.end_exact = rec.ref_blu == p.program_end_blu();
    r.moves_out = planner.naive_cam().moves_out();
    return r;
  };
  // The merged lines, in order, each hold the original vertices they replace within Q and end
  // exactly on an original vertex.
  {
    const auto mv = merged_moves(polyline(1500, 0.003, "G64 P0.01 Q0.01", &pts), m);
    std::size_t v = 1;  // pts[1] = (10, 0): the polyline's start
    double worst = 0.0;
    for (const gm::Motion& mo : mv) {
      if (mo.kind != gm::MotionKind::Line) continue;
      const double ex = mo.end_mm[0], ey = mo.end_mm[1];
      for (++v; v < pts.size() && (pts[v].first != ex || pts[v].second != ey); ++v)
        worst = std::max(
            worst, q_seg_dist(pts[v].first, pts[v].second, mo.start_mm[0], mo.start_mm[1], ex, ey));
      REQUIRE(v < pts.size());  // ends on an original vertex, in order
    }
    CHECK(v == pts.size() - 1);
    CHECK(worst > 0.001);  // something was merged across the wobble
    CHECK(worst <= 0.01);
  }
  const Result p_only = run("G64 P0.01");
  const Result pq = run("G64 P0.01 Q0.01");
  CHECK_FALSE(p_only.exceeded);
  CHECK_FALSE(pq.exceeded);
  CHECK(p_only.end_exact);
  CHECK(pq.end_exact);
  CHECK(p_only.worst_to_program_mm <= 0.01 + 1e-3);  // the polyline (+ 1 BLU of measurement)
  CHECK(pq.worst_to_program_mm <= 0.02 + 1e-3);      // P from the merged line, Q from it
  CHECK(pq.moves_out < 1503 / 4);
  CHECK(pq.cycle_s < p_only.cycle_s);
  // P alone plans the wobbling chords as runs of small turns (κ_eff, δ): 8.4 s when this was
  // written, where corner by corner took 12.35 s (docs/tolerance.md); 5.104 s measured
  // 2026-12-01, merged by Q 4.524 s.
  CHECK(p_only.cycle_s < 5.5);
  WARN(
      fmt::format("polyline 1500 x 0.02 mm: P0.01 {:.3f} s, worst {:.4f} mm; P0.01 Q0.01 {:.3f} s, "
                  "{} moves, worst {:.4f} mm to the program",
                  p_only.cycle_s, p_only.worst_to_program_mm, pq.cycle_s, pq.moves_out,
                  pq.worst_to_program_mm));
}
