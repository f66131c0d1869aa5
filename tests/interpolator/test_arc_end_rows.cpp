// ArcEndRows and the rule that commands them: an arc's ends in two directions, against the
// figures of an independent implementation of the fit (numpy).
#include "accdec/taps.hpp"
#include "interpolator/arc_compensation.hpp"
#include "interpolator/arc_end_fit.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace {

constexpr double kPeriod = 0.004;

std::vector<double> blackman() {
  static const gm::Taps t = gm::design_taps("blackman", 0.164, kPeriod);
  std::vector<double> h;
  for (auto b : t.integer) h.push_back(static_cast<double>(b) / static_cast<double>(t.b_s));
  return h;
}

// The command ArcCompensation gives each sample of a run, as ArcOffsets: the rows by the
// sample's advances from the start and to the end at its own speed (the interpolator's rule).
gm::ArcOffsets commanded(const gm::ArcCompensation& rule, const gm::ArcEndFit& fit,
                         const gm::ArcRun& run, double length_mm) {
  const std::vector<gm::ArcSample> smp = fit.samples(run);
  gm::ArcOffsets off{std::vector<double>(smp.size(), 0.0), std::vector<double>(smp.size(), 0.0)};
  for (std::size_t i = 0; i < smp.size(); ++i) {
    if (!smp[i].on) continue;
    const auto o = rule.offset(run.radius_mm, smp[i].x, smp[i].s_mm / smp[i].advance_mm,
                               (length_mm - smp[i].s_mm) / smp[i].advance_mm, 1.0, 1.0, false);
    off.radial_mm[i] = o.radial_mm;
    off.along_mm[i] = o.along_mm;
  }
  return off;
}

}  // namespace

TEST_CASE("the end rows: their knots and what they leave, as the numpy fit finds them",
          "[arc-end-rows]") {
  // The same fit in numpy (power means of |y − x(s̄)| raised to p = 128 by Newton steps, μ =
  // 1e-4, eight phases (j + 0.5)/8 of the join; the knots at rates 0.02, 0.1, 0.3, 0.55, 0.8 and 1 of
  // the limit 0.208643 of Blackman 0.164 s at 4 ms): radial at u = 1, 2, 3, then along, and
  // the worst over the phases over the steady loss. The problem is convex, so two solvers must
  // agree.
  const gm::ArcCompensation rule(blackman(), kPeriod);
  REQUIRE(rule.limit_omega_t() == Approx(0.2086431).epsilon(1e-6));
  const gm::ArcEndFit measure(blackman(), kPeriod);
  const int window = static_cast<int>(blackman().size());
  struct Knot {
    double frac;
    std::array<double, 6> u;
    double worst;
  };
  for (const Knot k : {Knot{0.1, {-1.646, 1.383, 4.026, -0.587, 1.221, -0.657}, 0.0745},
                       Knot{0.55, {-1.649, 1.157, 3.640, -0.732, 1.632, -1.163}, 0.0826},
                       Knot{1.0, {-1.511, 0.882, 3.018, -0.620, 1.161, -1.219}, 0.1184}}) {
    const double x = k.frac * rule.limit_omega_t(), c = 1.0 / rule.gain(x) - 1.0;
    CAPTURE(k.frac);
    for (int j = 0; j < 3; ++j) {
      const auto o = rule.offset(1.0, x, j + 1.0, 1e9, 1.0, 1.0, false);
      CHECK(o.radial_mm / c == Approx(k.u[static_cast<std::size_t>(j)]).margin(0.005));
      CHECK(o.along_mm * x / c == Approx(k.u[static_cast<std::size_t>(3 + j)]).margin(0.005));
    }
    double worst = 0.0;
    for (int p = 0; p < 8; ++p) {
      const gm::ArcRun run = gm::ArcRun::constant(1.0, std::numeric_limits<double>::infinity(),
                                                  x / kPeriod, kPeriod, (p + 0.5) / 8, window);
      worst = std::max(worst, measure.worst_fraction(run, commanded(rule, measure, run, 1e9),
                                                     gm::ArcEndMeasure::FromMean));
    }
    CHECK(worst == Approx(k.worst).margin(0.0005));
  }
}

TEST_CASE("a long arc's two ends by the rows, between knots: 7-10 % where the blend leaves 19-29 %",
          "[arc-end-rows]") {
  // numpy, the same rule (knots read linearly in the rate, both ends, the exit's along part
  // reversed) on a unit arc of 300.5 samples at constant speed: |y − x(s̄)| and the distance
  // from the path over the steady loss, the rows and the radial blend.
  const gm::ArcCompensation rule(blackman(), kPeriod);
  const gm::ArcEndFit measure(blackman(), kPeriod);
  const int window = static_cast<int>(blackman().size());
  struct Case {
    double frac, phase, rows, blend, rows_distance, blend_distance;
  };
  for (const Case c : {Case{0.3, 0.25, 0.0741, 0.1877, 0.0735, 0.1734},
                       Case{0.45, 0.37, 0.0793, 0.2047, 0.0789, 0.1707},
                       Case{0.8, 0.9, 0.0983, 0.2869, 0.0958, 0.1610}}) {
    const double x = c.frac * rule.limit_omega_t(), th = 300.5 * x;
    const gm::ArcRun run = gm::ArcRun::constant(1.0, th, x / kPeriod, kPeriod, c.phase, window);
    const gm::ArcOffsets rows = commanded(rule, measure, run, th);
    const gm::ArcOffsets blend = measure.linear_blend(run);
    CAPTURE(c.frac, c.phase);
    CHECK(measure.worst_fraction(run, rows, gm::ArcEndMeasure::FromMean) ==
          Approx(c.rows).margin(0.001));
    CHECK(measure.worst_fraction(run, blend, gm::ArcEndMeasure::FromMean) ==
          Approx(c.blend).margin(0.001));
    CHECK(measure.worst_fraction(run, rows) == Approx(c.rows_distance).margin(0.001));
    CHECK(measure.worst_fraction(run, blend) == Approx(c.blend_distance).margin(0.001));
  }
}

