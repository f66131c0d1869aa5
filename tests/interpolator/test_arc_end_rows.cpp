// ArcEndFit: a pre-compensated arc's entry corrected in two directions, judged by the distance of
// the Acc/Dec output from the path, against the figures of tools/arc_end_model.py (numpy, an
// independent implementation; docs/tolerance.md, "The arc's ends in two directions").
#include "accdec/taps.hpp"
#include "interpolator/arc_end_rows.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <vector>

namespace {

std::vector<double> blackman_weights() {
  static const gm::Taps t = gm::design_taps("blackman", 0.164, 0.004);
  std::vector<double> h;
  for (auto b : t.integer) h.push_back(static_cast<double>(b) / static_cast<double>(t.b_s));
  return h;
}

int window() {
  return static_cast<int>(blackman_weights().size());
}

// The model's profiles: the line at `ratio` of the arc's rate x stepping to x at the join.
gm::ArcEndSpeeds step_at_join(double x, double ratio, double phase) {
  gm::ArcEndSpeeds s;
  const int w = window();
  s.x.assign(static_cast<std::size_t>(3 * w), ratio * x);
  s.x.resize(static_cast<std::size_t>(7 * w), x);
  s.join = 3 * w;
  s.phase = phase;
  return s;
}

// The interpolator's ramp (x/window per sample) from 0.4·x to x, the join half-way along it.
gm::ArcEndSpeeds ramp_through_join(double x, double phase) {
  gm::ArcEndSpeeds s;
  const int w = window();
  s.x.assign(static_cast<std::size_t>(3 * w), 0.4 * x);
  std::vector<double> up;
  for (double v = 0.4 * x; v < x - 1e-12;) up.push_back(v = std::min(x, v + x / w));
  s.x.insert(s.x.end(), up.begin(), up.end());
  s.x.resize(s.x.size() + static_cast<std::size_t>(4 * w), x);
  s.join = 3 * w + static_cast<int>(up.size()) / 2;
  s.phase = phase;
  return s;
}

}  // namespace

TEST_CASE("today's radial blend leaves the model's 17 % of the steady loss at an entry",
          "[arc-end-rows]") {
  // tools/arc_end_model.py, first table, "today": 0.175, 0.174, 0.169 (x = 0.03, 0.06, 0.1).
  const gm::ArcEndFit fit(blackman_weights());
  const double expected[] = {0.175, 0.174, 0.169};
  int k = 0;
  for (double x : {0.03, 0.06, 0.1}) {
    const auto sp = gm::ArcEndSpeeds::constant(x, 0.25, window());
    CHECK(fit.worst_fraction(sp, gm::ArcEndFit::linear_blend(0.25)) ==
          Approx(expected[k++]).margin(0.001));
  }
}

TEST_CASE("rows fitted in two directions leave about 3 % at constant speed", "[arc-end-rows]") {
  // The model: "2-D, arc's first 6 samples, lam 1e-3": 0.032, 0.028, 0.031.
  const gm::ArcEndFit fit(blackman_weights());
  const double expected[] = {0.032, 0.028, 0.031};
  int k = 0;
  for (double x : {0.03, 0.06, 0.1}) {
    const auto sp = gm::ArcEndSpeeds::constant(x, 0.25, window());
    const gm::ArcEndRows rows = fit.fit(sp);
    CHECK(fit.worst_fraction(sp, rows) == Approx(expected[k++]).margin(0.002));
    // The tangential part is what does it: the same radial rows without it leave 11-16 %.
    gm::ArcEndRows radial_only = rows;
    radial_only.tangential = {};
    CHECK(fit.worst_fraction(sp, radial_only) > 0.08);
  }
}

TEST_CASE("rows depend on the join's phase; fitted at each phase they stay near 3 %",
          "[arc-end-rows]") {
  const gm::ArcEndFit fit(blackman_weights());
  const auto at = gm::ArcEndSpeeds::constant(0.03, 0.25, window());
  const gm::ArcEndRows quarter = fit.fit(at);
  double worst_quarter = 0.0;
  for (double phase : {0.05, 0.5, 0.75, 0.99}) {
    const auto sp = gm::ArcEndSpeeds::constant(0.03, phase, window());
    CHECK(fit.worst_fraction(sp, fit.fit(sp)) < 0.036);
    worst_quarter = std::max(worst_quarter, fit.worst_fraction(sp, quarter));
  }
  // One phase's rows used at every phase: the model's "one phase for all" leaves 10 %.
  CHECK(worst_quarter == Approx(0.102).margin(0.003));
}

TEST_CASE("rows fitted for the speeds around the join: a step from the line, a ramp through it",
          "[arc-end-rows]") {
  // The model's last table, x = 0.03: today 0.092 / 0.350, fitted 0.019 / 0.055 / 0.018, the
  // worst over the join's phases 0.1, 0.4, 0.7, 0.95. (Today's blend on the ramp is not compared:
  // the model blends by path length at the arc's speed, linear_blend by samples.)
  const gm::ArcEndFit fit(blackman_weights());
  struct Case {
    double ratio;  // line speed / arc speed; 0: the ramp through the join
    double today, fitted;
  };
  for (const Case c : {Case{0.5, 0.092, 0.019}, Case{2.0, 0.350, 0.055}, Case{0.0, 0.0, 0.018}}) {
    double worst_today = 0.0, worst_fitted = 0.0;
    for (double phase : {0.1, 0.4, 0.7, 0.95}) {
      const auto sp =
          c.ratio > 0.0 ? step_at_join(0.03, c.ratio, phase) : ramp_through_join(0.03, phase);
      worst_today =
          std::max(worst_today, fit.worst_fraction(sp, gm::ArcEndFit::linear_blend(phase)));
      worst_fitted = std::max(worst_fitted, fit.worst_fraction(sp, fit.fit(sp)));
    }
    if (c.ratio > 0.0) CHECK(worst_today == Approx(c.today).margin(0.002));
    CHECK(worst_fitted == Approx(c.fitted).margin(0.004));
  }
}
