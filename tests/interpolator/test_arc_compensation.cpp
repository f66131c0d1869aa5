// Pre-compensated arcs in the interpolator: the commanded radius R + c from the sample's speed,
// the end rows, the speed ramp, exact ends, helices in another plane.
#include "accdec/taps.hpp"
#include "interpolator/interpolator.hpp"
#include "planner/filter_moments.hpp"

#include "support/canon_list.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace {

using gm::AxisVec;
using gm::Canon;
using gm::Motion;
using gm::xyz;

const gm::Taps& blackman() {
  static const gm::Taps t = gm::design_taps("blackman", 0.164, 0.004);
  return t;
}

std::vector<double> weights() {
  std::vector<double> h;
  for (auto b : blackman().integer)
    h.push_back(static_cast<double>(b) / static_cast<double>(blackman().b_s));
  return h;
}

gm::InterpolatorConfig compensated_config() {
  gm::InterpolatorConfig c;
  c.period_s = 0.004;
  c.blu_mm = AxisVec::Constant(0.001);
  c.arc_comp = gm::ArcCompensation(weights(), 0.004);
  return c;
}

// A half circle of radius 5 about (5, 0) from the origin, G3 in XY, F3000 (50 mm/s).
Motion half_circle(double comp_speed) {
  Motion m;
  m.kind = gm::MotionKind::Arc;
  m.start_mm = AxisVec::Zero();
  m.end_mm = xyz(10, 0, 0);
  m.center_mm = xyz(5, 0, 0);
  m.ccw = true;
  m.feed_mm_min = 3000;
  m.path_tolerance_mm = 0.01;
  m.comp_speed_mm_s = comp_speed;
  return m;
}

std::vector<gm::CommandSample> run(std::vector<Canon> canon, double (*scale)(std::int64_t)) {
  gmtest::CanonList src(std::move(canon));
  gm::Interpolator ip(compensated_config(), src);
  std::vector<gm::CommandSample> out;
  gm::CommandSample s;
  for (std::int64_t k = 0; k < 1'000'000; ++k) {
    gm::OverrideInput o;
    o.feed_scale = scale(k);
    if (ip.step(o, s) == gm::InterpStatus::Finished) break;
    out.push_back(s);
  }
  return out;
}

double full(std::int64_t) {
  return 1.0;
}

// The closed form's correction for radius r at ωT (planner/filter_moments).
double correction_mm(double r, double omega_t) {
  const gm::FilterMoments f(blackman(), 0.004);
  return f.compensated_radius_mm(r, omega_t) - r;
}

double radius_of(const gm::CommandSample& s, double cx, double cy) {
  return std::hypot(s.pos_blu[0] * 0.001 - cx, s.pos_blu[1] * 0.001 - cy);
}

}  // namespace

TEST_CASE("compensated arc: radius R + c(v) at speed, ramped from rest, end rows, ends exact") {
  const auto plain = run({half_circle(0.0)}, full);
  const auto comp = run({half_circle(50.0)}, full);
  // Uncompensated: on R = 5 within a BLU, 50 mm/s from the first sample.
  for (const auto& s : plain) CHECK(radius_of(s, 5, 0) == Approx(5.0).margin(0.0011));
  // From rest the speed ramps by 50/41 mm/s a sample (ramp_samples = N + 1 = 41, τ): the path
  // angle advanced after k samples is Σ min(50, 50·j/41)·T / R.
  const double c50 = correction_mm(5.0, 50.0 * 0.004 / 5.0);
  CHECK(c50 == Approx(5.0 * (1.0 / gm::FilterMoments(blackman(), 0.004).amplitude(0.04) - 1.0)));
  CHECK(c50 > 0.04);  // 5 mm at 50 mm/s under Blackman 0.164 s: about 43 µm
  // The end rows (arc_end_rows.hpp) over the first and last 4 samples: by the count since the
  // first sample plus its phase (from rest: a whole advance past the start, so 1, 2, 3) and by
  // the advances left, predicted by the ramp (advances_to_end); the steady c between.
  const gm::ArcCompensation rule(weights(), 0.004);
  const double length = 5.0 * std::numbers::pi;
  double s_mm = 0.0;
  int rows_at_ends = 0;
  for (std::size_t k = 0; k + 1 < comp.size(); ++k) {
    const double v = std::min(50.0, 50.0 / 41.0 * static_cast<double>(k + 1));
    s_mm += v * 0.004;
    const double ang = s_mm / 5.0;  // from the start ray (−1, 0) of the circle
    const double x = v * 0.004 / 5.0, from = static_cast<double>(k) + 1.0;
    const double to_end = rule.advances_to_end(length - s_mm, v, 50.0, 50.0 / 41.0,
                                               std::numeric_limits<double>::infinity());
    const auto off = rule.offset(5.0, x, from, to_end, 1.0, 1.0, false);
    if (from >= 4.0 && to_end >= 4.0) {  // between the ends: the closed form, radial only
      CHECK(off.radial_mm == Approx(correction_mm(5.0, x)).margin(2e-6));  // A from its table
      CHECK(off.along_mm == 0.0);
    } else {
      ++rows_at_ends;
    }
    // Outward (−cos, −sin) of the angle, along the motion (sin, −cos).
    const double r = 5.0 + off.radial_mm;
    CAPTURE(k, v, s_mm, to_end);
    CHECK(comp[k].pos_blu[0] * 0.001 ==
          Approx(5.0 - r * std::cos(ang) + off.along_mm * std::sin(ang)).margin(0.0006));
    CHECK(comp[k].pos_blu[1] * 0.001 ==
          Approx(-r * std::sin(ang) - off.along_mm * std::cos(ang)).margin(0.0006));
  }
  CHECK(rows_at_ends == 7);  // from rest 1, 2 and 3 advances, and the last 4
  CHECK(comp.back().pos_blu == gm::blu3(10000, 0, 0));  // the programmed end point exactly
  CHECK(comp.size() > plain.size());                    // the ramp from rest
}

namespace {
double hold_after_200(std::int64_t k) {
  return k < 200 ? 1.0 : 0.0;
}
}  // namespace

TEST_CASE("compensated arc: an override step is a ramp, and at rest the radius is R") {
  Motion m = half_circle(50.0);
  m.end_mm = m.start_mm;  // a full circle, three turns
  m.turns = 3;
  const auto s = run({m}, hold_after_200);
  // The path advance per sample changes by at most 50/41 mm/s·T = 0.0049 mm per sample.
  double prev_adv = 0.0;
  double angle_prev = std::atan2(0.0, -5.0);
  int still = 0;
  for (std::size_t k = 0; k < s.size() && k < 400; ++k) {
    const double a = std::atan2(s[k].pos_blu[1] * 0.001, s[k].pos_blu[0] * 0.001 - 5.0);
    double d = a - angle_prev;
    while (d < -std::numbers::pi) d += 2 * std::numbers::pi;
    while (d > std::numbers::pi) d -= 2 * std::numbers::pi;
    angle_prev = a;
    const double adv = std::abs(d) * 5.0;  // mm along the circle (radius changes aside)
    CAPTURE(k, adv, prev_adv);
    // Past the start's end rows (4 advances at the sample's speed: 8 samples into the ramp),
    // which also move the command along the circle.
    if (k >= 10) CHECK(std::abs(adv - prev_adv) <= 0.2 / 41.0 + 0.002);  // + two roundings
    prev_adv = adv;
    if (k > 250) {
      ++still;
      CHECK(adv == Approx(0.0).margin(1e-9));                      // held
      CHECK(radius_of(s[k], 5, 0) == Approx(5.0).margin(0.0011));  // c(0) = 0
    }
  }
  CHECK(still > 100);
}

TEST_CASE("compensated helix in G18: the correction is radial in ZX, Y follows its lead") {
  // XZ plane: in-plane axes (Z, X), normal Y. Centre (0, 0, 4), from (0,0,0) round to (0,0,8)
  // with 6 mm of Y.
  Motion m;
  m.kind = gm::MotionKind::Arc;
  m.plane = gm::Plane::XZ;
  m.start_mm = xyz(0, 0, 0);
  m.end_mm = xyz(0, 6, 8);
  m.center_mm = xyz(0, 0, 4);
  m.ccw = true;
  m.feed_mm_min = 3000;
  m.comp_speed_mm_s = 50.0;
  const auto s = run({m}, full);
  const double th = std::numbers::pi, R = 4.0, L = std::hypot(R * th, 6.0);
  const double c = correction_mm(R, 50.0 * th / L * 0.004);
  int steady = 0;
  for (std::size_t k = 0; k + 1 < s.size(); ++k) {
    const double x = s[k].pos_blu[0] * 0.001, y = s[k].pos_blu[1] * 0.001,
                 z = s[k].pos_blu[2] * 0.001;
    const double r = std::hypot(x, z - 4.0);
    const double frac = y / 6.0;  // Y is linear in the path fraction
    const double s_mm = frac * L;
    if (s_mm > 42 * 50.0 * 0.004 &&
        s_mm < L - 4 * 50.0 * 0.004) {  // past the ramp, before the rows
      ++steady;
      CHECK(r == Approx(R + c).margin(0.0012));
      // The point lies on the ray of its path fraction (radial correction only).
      const double ang = frac * th;
      // Half a BLU in Y moves the angle by π·0.0005/6, in Z and X by 0.0005·√2/R.
      CHECK(std::atan2(-x, -(z - 4.0)) == Approx(ang).margin(0.0006));
    }
  }
  CHECK(steady > 20);
  CHECK(s.back().pos_blu == gm::blu3(0, 6000, 8000));
}

namespace {
// The half circle cut at its middle (5, −5) into two pieces of the same centre, as the planner
// cuts an arc at a zone boundary: where each lies in the whole arc, and the second's cap.
std::vector<Canon> half_circle_in_pieces(double second_cap_mm_s) {
  const double length = 5.0 * std::numbers::pi;
  Motion a = half_circle(50.0), b = half_circle(50.0);
  a.end_mm = b.start_mm = xyz(5, -5, 0);
  a.comp_arc_length_mm = b.comp_arc_length_mm = length;
  b.comp_arc_from_mm = 0.5 * length;
  if (second_cap_mm_s > 0.0) {
    b.speed_cap_mm_s = second_cap_mm_s;
    a.comp_exit_speed_mm_s = second_cap_mm_s;
  }
  return {a, b};
}
}  // namespace

TEST_CASE("compensated arc in pieces: the whole arc's command, and a brake to the next cap") {
  // Cut without a cap: the same samples as the arc whole (the count, the end rows and the
  // ramp are the whole arc's), to a BLU (each piece's angle is its own sum).
  const auto whole = run({half_circle(50.0)}, full);
  const auto cut = run(half_circle_in_pieces(0.0), full);
  REQUIRE(cut.size() == whole.size());
  for (std::size_t k = 0; k < cut.size(); ++k) {
    CAPTURE(k);
    CHECK(std::abs(cut[k].pos_blu[0] - whole[k].pos_blu[0]) <= 1);
    CHECK(std::abs(cut[k].pos_blu[1] - whole[k].pos_blu[1]) <= 1);
  }
  // The second piece capped at 20 mm/s: the first brakes to it by the ramp (50/41 mm/s a
  // sample) before the cut, so the advance never changes by more than a step, and it is at
  // most 20 mm/s·T past the cut.
  const auto braked = run(half_circle_in_pieces(20.0), full);
  double prev_adv = 0.0, angle_prev = std::atan2(0.0, -5.0);
  int past_cut = 0;
  for (std::size_t k = 0; k + 1 < braked.size(); ++k) {
    const double a = std::atan2(braked[k].pos_blu[1] * 0.001, braked[k].pos_blu[0] * 0.001 - 5.0);
    double d = a - angle_prev;
    while (d < -std::numbers::pi) d += 2 * std::numbers::pi;
    while (d > std::numbers::pi) d -= 2 * std::numbers::pi;
    angle_prev = a;
    const double adv = std::abs(d) * 5.0;
    CAPTURE(k, adv, prev_adv);
    // Past the start's end rows and before the end's (their along-path offsets).
    if (k >= 10 && k + 6 < braked.size())
      CHECK(std::abs(adv - prev_adv) <= 0.2 / 41.0 + 0.002);  // + two roundings
    // Past the cut at (5, −5), the angle 3π/2 from the centre: at most the cap.
    if (a > -std::numbers::pi / 2 + 0.01 && a < 0.0 && k + 6 < braked.size()) {
      ++past_cut;
      CHECK(adv <= 20.0 * 0.004 + 0.002);
    }
    prev_adv = adv;
  }
  CHECK(past_cut > 20);
  CHECK(braked.back().pos_blu == gm::blu3(10000, 0, 0));
  CHECK(braked.size() > whole.size());
}
