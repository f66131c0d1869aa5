// ArcEndFit: a pre-compensated arc's output measured against the path, by the figures of
// tools/arc_end_model.py (numpy, an independent implementation), and its fit by a closed form.
#include "accdec/taps.hpp"
#include "interpolator/arc_end_fit.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <tuple>
#include <utility>
#include <vector>

namespace {

constexpr double kFitPeriod = 0.004;
constexpr double kFitEndless = std::numeric_limits<double>::infinity();

std::vector<double> fit_weights() {
  static const gm::Taps t = gm::design_taps("blackman", 0.164, kFitPeriod);
  std::vector<double> h;
  for (auto b : t.integer) h.push_back(static_cast<double>(b) / static_cast<double>(t.b_s));
  return h;
}

int fit_window() {
  return static_cast<int>(fit_weights().size());
}

// An endless arc of radius 1 entered at the given speeds (the model's speed cases).
gm::ArcRun fit_entry(std::vector<double> speeds, int first, double phase, double planned) {
  gm::ArcRun run;
  run.speed_mm_s = std::move(speeds);
  run.first = first;
  run.phase = phase;
  run.planned_mm_s = planned;
  return run;
}

// The interpolator's ramp on a compensated arc (v/window per sample) from a to b, exclusive of a.
std::vector<double> fit_ramp(double a, double b, double v) {
  std::vector<double> out;
  for (double s = a; std::abs(s - b) > 1e-12;)
    out.push_back(s = b > a ? std::min(b, s + v / fit_window())
                            : std::max(b, s - v / fit_window()));
  return out;
}

}  // namespace

TEST_CASE("an entry into a long arc: the radial blend leaves 17 % of the steady loss",
          "[arc-end-fit]") {
  // tools/arc_end_model.py, first table, "today": 0.175, 0.174, 0.169 of the distance and 0.178,
  // 0.187, 0.209 of |y − x(s̄)| (x = 0.03, 0.06, 0.1, phase 0.25).
  const gm::ArcEndFit fit(fit_weights(), kFitPeriod);
  struct Case {
    double x, distance, from_mean;
  };
  for (const Case c :
       {Case{0.03, 0.175, 0.178}, Case{0.06, 0.174, 0.187}, Case{0.1, 0.169, 0.209}}) {
    const auto run =
        gm::ArcRun::constant(1.0, kFitEndless, c.x / kFitPeriod, kFitPeriod, 0.25, fit_window());
    CHECK(fit.worst_fraction(run, fit.linear_blend(run)) == Approx(c.distance).margin(0.001));
    CHECK(fit.worst_fraction(run, fit.linear_blend(run), gm::ArcEndMeasure::FromMean) ==
          Approx(c.from_mean).margin(0.001));
  }
}

TEST_CASE("the fit on a steady circle finds the compensated radius R/A", "[arc-end-fit]") {
  // A circle from its first sample on (no line in the windows measured): one unknown scaling c
  // on every sample. The output is A·(r + u·c) on the mean angle, so |y − x(s̄)| = A·c·|1 − u|
  // and M_p² + μc²u² is least at u = A²/(A² + μ): 1 at μ = 0 (the paper's R/A), 1/1.01 at
  // μ = 0.01·A².
  const gm::ArcEndFit fit(fit_weights(), kFitPeriod);
  for (double x : {0.02, 0.08, 0.15}) {
    gm::ArcRun run =
        gm::ArcRun::constant(2.0, kFitEndless, 2.0 * x / kFitPeriod, kFitPeriod, 0.5, fit_window());
    run.first = 0;
    const std::vector<gm::ArcSample> smp = fit.samples(run);
    const std::size_t n = smp.size();
    gm::ArcCommandModel model{{std::vector<double>(n, 0.0), std::vector<double>(n, 0.0)}, {}};
    model.columns.push_back(model.base);
    for (std::size_t i = 0; i < n; ++i) model.columns[0].radial_mm[i] = smp[i].c_mm;
    const double a = fit.gain(x);
    CAPTURE(x);
    CHECK(fit.fit_shared({run}, {model}, 0.0)[0] == Approx(1.0).epsilon(1e-6));
    CHECK(fit.fit_shared({run}, {model}, 0.01 * a * a)[0] == Approx(1.0 / 1.01).epsilon(1e-6));
  }
}

TEST_CASE("whole arcs, arcs shorter than the window included: the radial blend", "[arc-end-fit]") {
  // tools/arc_end_model.py, "Whole arcs": today.
  const gm::ArcEndFit fit(fit_weights(), kFitPeriod);
  struct Case {
    double r_mm, sweep_deg, v_mm_s, today;
  };
  for (const Case c : {Case{1, 90, 13.5, 0.174}, Case{1, 90, 25, 0.175}, Case{2, 180, 18, 0.175},
                       Case{4, 180, 26, 0.175}}) {
    const auto run = gm::ArcRun::constant(c.r_mm, c.sweep_deg * std::numbers::pi / 180.0, c.v_mm_s,
                                          kFitPeriod, 0.25, fit_window());
    CHECK(fit.worst_fraction(run, fit.linear_blend(run)) == Approx(c.today).margin(0.001));
  }
}

TEST_CASE("the radial blend where the speed changes at the join: steps, ramps, from rest",
          "[arc-end-fit]") {
  // tools/arc_end_model.py, the speed cases at x = 0.03, the worst distance over the join's
  // phases 0.1, 0.4, 0.7 and 0.95, today: 0.092 (line at 0.5 v), 0.350 (line at 2 v), 0.101
  // (ramp 0.4 v to v through the join), 0.094 (v to 0.4 v), 0.013 (from rest).
  const gm::ArcEndFit fit(fit_weights(), kFitPeriod);
  const int w = fit_window();
  const double v = 0.03 / kFitPeriod;
  struct Case {
    std::vector<double> speeds;
    int first;
    double today;
  };
  std::vector<Case> cases;
  auto step = [&](double before) {
    std::vector<double> s(static_cast<std::size_t>(3 * w), before);
    s.resize(static_cast<std::size_t>(7 * w), v);
    return s;
  };
  auto through = [&](double from, double to) {
    const auto r = fit_ramp(from, to, v);
    std::vector<double> s(static_cast<std::size_t>(3 * w), from > 0.0 ? from : 1e-9);
    s.insert(s.end(), r.begin(), r.end());
    s.resize(s.size() + static_cast<std::size_t>(4 * w), to);
    return std::pair{s, from > 0.0 ? 3 * w + static_cast<int>(r.size()) / 2 : 3 * w};
  };
  cases.push_back({step(0.5 * v), 3 * w, 0.092});
  cases.push_back({step(2.0 * v), 3 * w, 0.350});
  for (const auto& [from, to, today] :
       {std::tuple{0.4 * v, v, 0.101}, std::tuple{v, 0.4 * v, 0.094}, std::tuple{0.0, v, 0.013}}) {
    auto [s, first] = through(from, to);
    cases.push_back({s, first, today});
  }
  for (const Case& c : cases) {
    double worst_today = 0.0;
    for (double phase : {0.1, 0.4, 0.7, 0.95}) {
      const gm::ArcRun run = fit_entry(c.speeds, c.first, phase, v);
      worst_today = std::max(worst_today, fit.worst_fraction(run, fit.linear_blend(run)));
    }
    CHECK(worst_today == Approx(c.today).margin(0.001));
  }
}
