// ArcEndFit: a pre-compensated arc's ends corrected in two directions, judged by the distance of
// the Acc/Dec output from the path, against the figures of tools/arc_end_model.py (numpy, an
// independent implementation; docs/tolerance.md, "The arc's ends in two directions").
#include "accdec/taps.hpp"
#include "interpolator/arc_end_rows.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <tuple>
#include <utility>
#include <vector>

namespace {

constexpr double kPeriod = 0.004;
constexpr double kEndless = std::numeric_limits<double>::infinity();

std::vector<double> blackman_weights() {
  static const gm::Taps t = gm::design_taps("blackman", 0.164, kPeriod);
  std::vector<double> h;
  for (auto b : t.integer) h.push_back(static_cast<double>(b) / static_cast<double>(t.b_s));
  return h;
}

int window() {
  return static_cast<int>(blackman_weights().size());
}

// An endless arc of radius 1 entered at the given speeds (the model's speed cases).
gm::ArcRun entry(std::vector<double> speeds, int first, double phase, double planned) {
  gm::ArcRun run;
  run.speed_mm_s = std::move(speeds);
  run.first = first;
  run.phase = phase;
  run.planned_mm_s = planned;
  return run;
}

// The interpolator's ramp on a compensated arc (v/window per sample) from a to b, exclusive of a.
std::vector<double> ramp(double a, double b, double v) {
  std::vector<double> out;
  for (double s = a; std::abs(s - b) > 1e-12;)
    out.push_back(s = b > a ? std::min(b, s + v / window()) : std::max(b, s - v / window()));
  return out;
}

}  // namespace

TEST_CASE("an entry into a long arc: today's blend 17 %, two directions 3 % of the steady loss",
          "[arc-end-rows]") {
  // tools/arc_end_model.py, first table: today 0.175, 0.174, 0.169; "2-D, arc's first 6
  // samples, lam 1e-3" 0.032, 0.028, 0.031 (x = 0.03, 0.06, 0.1, phase 0.25).
  const gm::ArcEndFit fit(blackman_weights(), kPeriod);
  struct Case {
    double x, today, fitted;
  };
  for (const Case c :
       {Case{0.03, 0.175, 0.032}, Case{0.06, 0.174, 0.028}, Case{0.1, 0.169, 0.031}}) {
    const auto run = gm::ArcRun::constant(1.0, kEndless, c.x / kPeriod, kPeriod, 0.25, window());
    CHECK(fit.worst_fraction(run, fit.linear_blend(run)) == Approx(c.today).margin(0.001));
    const gm::ArcOffsets off = fit.fit(run);
    CHECK(fit.worst_fraction(run, off) == Approx(c.fitted).margin(0.001));
    // The tangential part is what does it: the same offsets without it leave far more.
    gm::ArcOffsets radial_only = off;
    std::fill(radial_only.along_mm.begin(), radial_only.along_mm.end(), 0.0);
    CHECK(fit.worst_fraction(run, radial_only) > 0.08);
  }
}

TEST_CASE("whole arcs, both ends fitted together, arcs shorter than the window included",
          "[arc-end-rows]") {
  // tools/arc_end_model.py, "Whole arcs": today and "2-D, 6 + 6 samples".
  const gm::ArcEndFit fit(blackman_weights(), kPeriod);
  struct Case {
    double r_mm, sweep_deg, v_mm_s, today, fitted;
  };
  for (const Case c : {Case{1, 90, 13.5, 0.174, 0.030}, Case{1, 90, 25, 0.175, 0.036},
                       Case{2, 180, 18, 0.175, 0.032}, Case{4, 180, 26, 0.175, 0.033}}) {
    const auto run = gm::ArcRun::constant(c.r_mm, c.sweep_deg * std::numbers::pi / 180.0, c.v_mm_s,
                                          kPeriod, 0.25, window());
    CHECK(fit.worst_fraction(run, fit.linear_blend(run)) == Approx(c.today).margin(0.001));
    CHECK(fit.worst_fraction(run, fit.fit(run)) == Approx(c.fitted).margin(0.002));
  }
}

TEST_CASE("offsets fitted for the speeds around the join: steps from the line, ramps, from rest",
          "[arc-end-rows]") {
  // tools/arc_end_model.py, the speed cases at x = 0.03, the worst over the join's phases 0.1,
  // 0.4, 0.7 and 0.95: today / fitted 0.092 / 0.019 (line at 0.5 v), 0.350 / 0.055 (line at
  // 2 v), 0.101 / 0.018 (ramp 0.4 v to v through the join), 0.094 / 0.025 (v to 0.4 v),
  // 0.013 / 0.013 (from rest).
  const gm::ArcEndFit fit(blackman_weights(), kPeriod);
  const int w = window();
  const double v = 0.03 / kPeriod;
  struct Case {
    std::vector<double> speeds;
    int first;
    double today, fitted;
  };
  std::vector<Case> cases;
  auto step = [&](double before) {
    std::vector<double> s(static_cast<std::size_t>(3 * w), before);
    s.resize(static_cast<std::size_t>(7 * w), v);
    return s;
  };
  auto through = [&](double from, double to) {
    const auto r = ramp(from, to, v);
    std::vector<double> s(static_cast<std::size_t>(3 * w), from > 0.0 ? from : 1e-9);
    s.insert(s.end(), r.begin(), r.end());
    s.resize(s.size() + static_cast<std::size_t>(4 * w), to);
    return std::pair{s, from > 0.0 ? 3 * w + static_cast<int>(r.size()) / 2 : 3 * w};
  };
  cases.push_back({step(0.5 * v), 3 * w, 0.092, 0.019});
  cases.push_back({step(2.0 * v), 3 * w, 0.350, 0.055});
  for (const auto& [from, to, today, fitted] :
       {std::tuple{0.4 * v, v, 0.101, 0.018}, std::tuple{v, 0.4 * v, 0.094, 0.025},
        std::tuple{0.0, v, 0.013, 0.013}}) {
    auto [s, first] = through(from, to);
    cases.push_back({s, first, today, fitted});
  }
  for (const Case& c : cases) {
    double worst_today = 0.0, worst_fitted = 0.0;
    for (double phase : {0.1, 0.4, 0.7, 0.95}) {
      const gm::ArcRun run = entry(c.speeds, c.first, phase, v);
      worst_today = std::max(worst_today, fit.worst_fraction(run, fit.linear_blend(run)));
      worst_fitted = std::max(worst_fitted, fit.worst_fraction(run, fit.fit(run)));
    }
    CHECK(worst_today == Approx(c.today).margin(0.001));
    CHECK(worst_fitted == Approx(c.fitted).margin(0.002));
  }
}
