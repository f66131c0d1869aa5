// ArcEndRows and the rule that commands them: an arc's ends in two directions, against the
// figures of an independent implementation of the fit (numpy).
#include "accdec/taps.hpp"
#include "interpolator/arc_compensation.hpp"
#include "interpolator/arc_end_fit.hpp"
#include "interpolator/arc_end_rows.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <thread>
#include <vector>

namespace {

constexpr double kRowsPeriod = 0.004;

std::vector<double> rows_weights() {
  static const gm::Taps t = gm::design_taps("blackman", 0.164, kRowsPeriod);
  std::vector<double> h;
  for (auto b : t.integer) h.push_back(static_cast<double>(b) / static_cast<double>(t.b_s));
  return h;
}

// The command ArcCompensation gives each sample of a run, as ArcOffsets: the rows by the
// sample's advances from the start and to the end at its own speed (the interpolator's rule).
gm::ArcOffsets rows_command(const gm::ArcCompensation& rule, const gm::ArcEndFit& fit,
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

TEST_CASE("the end rows' knots as the numpy fit finds them", "[arc-end-rows]") {
  // tools/arc_end_rows_model.py (numpy: the same runs, power means of |y − x(s̄)| raised to
  // p = 128 by Newton steps, μ = 1e-4), Blackman 0.164 s at 4 ms, limit 0.2086431: radial at
  // u = 1, 2, 3, then along in units of c; Moving at the rate knots 0.1 and 0.8 of the limit,
  // Stopping at 0.55 and 1. The problem is convex, so two solvers must agree.
  const gm::ArcCompensation rule(rows_weights(), kRowsPeriod);
  REQUIRE(rule.limit_omega_t() == Approx(0.2086431).epsilon(1e-6));
  struct Knot {
    double frac;
    bool stopping;
    std::array<double, 6> k;
  };
  for (const Knot k : {Knot{0.1, false, {-0.625, 1.189, 3.103, -11.813, 22.838, -11.661}},
                       Knot{0.8, false, {-0.298, 0.970, 2.210, -2.021, 3.183, -3.357}},
                       Knot{0.55, true, {0.195, 0.601, 0.540, -0.336, 1.161, -1.968}},
                       Knot{1.0, true, {-0.018, 0.315, 0.385, 0.068, 2.359, -4.187}}}) {
    const double x = k.frac * rule.limit_omega_t(), c = 1.0 / rule.gain(x) - 1.0;
    CAPTURE(k.frac, k.stopping);
    for (int j = 0; j < 3; ++j) {
      const double u = j + 1.0;
      // A start (Moving) or an end (Stopping: its along part reversed).
      const auto o = k.stopping ? rule.offset(1.0, x, 1e9, u, 1.0, 1.0, true)
                                : rule.offset(1.0, x, u, 1e9, 1.0, 1.0, false);
      const double along = k.stopping ? -o.along_mm : o.along_mm;
      const double tol = 0.002 * (1.0 + std::abs(k.k[static_cast<std::size_t>(3 + j)]));
      CHECK(o.radial_mm / c == Approx(k.k[static_cast<std::size_t>(j)]).margin(0.003));
      CHECK(along / c == Approx(k.k[static_cast<std::size_t>(3 + j)]).margin(tol));
    }
  }
}

TEST_CASE("a long arc's two ends by the rows, between knots: 9-13 % where the blend leaves 19-29 %",
          "[arc-end-rows]") {
  // tools/arc_end_rows_model.py, the same rule (knots read linearly in the rate, both ends,
  // the exit's along part reversed) on a unit arc of 300.5 samples at constant speed: |y −
  // x(s̄)| and the distance from the path over the steady loss, the rows and the radial blend.
  const gm::ArcCompensation rule(rows_weights(), kRowsPeriod);
  const gm::ArcEndFit measure(rows_weights(), kRowsPeriod);
  const int window = static_cast<int>(rows_weights().size());
  struct Case {
    double frac, phase, rows, blend, rows_distance, blend_distance;
  };
  for (const Case c : {Case{0.3, 0.25, 0.0908, 0.1877, 0.0901, 0.1734},
                       Case{0.45, 0.37, 0.0973, 0.2047, 0.0956, 0.1707},
                       Case{0.8, 0.9, 0.1265, 0.2869, 0.1201, 0.1610}}) {
    const double x = c.frac * rule.limit_omega_t(), th = 300.5 * x;
    const gm::ArcRun run =
        gm::ArcRun::constant(1.0, th, x / kRowsPeriod, kRowsPeriod, c.phase, window);
    const gm::ArcOffsets rows = rows_command(rule, measure, run, th);
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

TEST_CASE("the rows are the same whichever thread fits them, and stop cleanly", "[arc-end-rows]") {
  // The first set asked for starts a thread fitting the others; callers racing it wait for a
  // set it has begun or fit one it has not. Every knot must come out bit for bit the same as
  // one fitted with nobody else asking: here, rows asked for set by set from one thread, in
  // the order the background thread takes them, against rows asked for from three threads at
  // once in other orders (a set is the same fit whoever runs it).
  const std::vector<double> h = rows_weights();
  const double limit = gm::ArcCompensation(h, kRowsPeriod).limit_omega_t();
  constexpr std::size_t kRates = gm::ArcEndRows::kRateKnots.size();
  using Way = gm::ArcEndRows::Way;
  // One probe per rate knot and way: at a knot, at() reads that set (and its neighbour's with
  // weight 0), at u = 1.5 both knots' radial and along values take part.
  auto probe = [&](const gm::ArcEndRows& rows, std::size_t rate, Way way) {
    const auto s = rows.at(1.5, gm::ArcEndRows::kRateKnots[rate] * limit, way);
    return std::array<double, 2>{s.radial, s.along};
  };
  std::array<std::array<double, 2>, 2 * kRates> alone{};
  {
    const gm::ArcEndRows rows(h, kRowsPeriod, limit);
    for (std::size_t r = 0; r < kRates; ++r)
      for (Way w : {Way::Moving, Way::Stopping})
        alone[2 * r + (w == Way::Moving ? 0 : 1)] = probe(rows, r, w);
  }
  const gm::ArcEndRows rows(h, kRowsPeriod, limit);
  std::array<std::array<double, 2>, 2 * kRates> raced[3]{};
  std::vector<std::thread> askers;
  for (int t = 0; t < 3; ++t)
    askers.emplace_back([&, t] {
      for (std::size_t i = 0; i < 2 * kRates; ++i) {
        // Thread 0 from the top, 1 from the bottom, 2 from the middle outwards.
        const std::size_t j = t == 0   ? 2 * kRates - 1 - i
                              : t == 1 ? i
                                       : (i + kRates) % (2 * kRates);
        raced[t][j] = probe(rows, j / 2, j % 2 == 0 ? Way::Moving : Way::Stopping);
      }
    });
  for (std::thread& a : askers) a.join();
  for (int t = 0; t < 3; ++t)
    for (std::size_t j = 0; j < 2 * kRates; ++j) {
      CAPTURE(t, j);
      CHECK(raced[t][j][0] == alone[j][0]);
      CHECK(raced[t][j][1] == alone[j][1]);
    }
  // Rows dropped right after their first set: the background thread stops after the set in
  // hand (the destructor waits for it; a test that hangs or races here fails under TSan).
  for (int i = 0; i < 3; ++i) {
    const gm::ArcEndRows early(h, kRowsPeriod, limit);
    CHECK(probe(early, 2, Way::Moving) == alone[4]);
  }
}

TEST_CASE("the rows fitted for the distance: half the shared rows' distance, between knots too",
          "[arc-end-rows]") {
  // A unit arc of 300.5 samples at constant speed, both ends by ArcEndRows::Way::MovingDistance
  // (ArcCompensation::offset with start_distance and end_distance): the worst distance from the
  // path over the steady loss, at rate knots (0.1, 0.3, 0.8 of the limit) and between them
  // (0.16, 0.45), where the along knots are read linearly in along·x (read linearly in along
  // the distance at 0.16 was 0.094, as much as the shared rows leave). Against the rows that
  // share their windows (Way::Moving): 0.089 to 0.120 of the loss at these rates, the
  // distance's 0.053 to 0.070 (0.048 to 0.064 when they were fitted without the runs whose
  // speed ramps on the line before the join). Their |y − x(s̄)| is larger: the output runs
  // ahead of s̄.
  const gm::ArcCompensation rule(rows_weights(), kRowsPeriod);
  const gm::ArcEndFit measure(rows_weights(), kRowsPeriod);
  const int window = static_cast<int>(rows_weights().size());
  for (const double frac : {0.1, 0.16, 0.3, 0.45, 0.8})
    for (const double phase : {0.1, 0.6}) {
      const double x = frac * rule.limit_omega_t(), th = 300.5 * x;
      const gm::ArcRun run =
          gm::ArcRun::constant(1.0, th, x / kRowsPeriod, kRowsPeriod, phase, window);
      const std::vector<gm::ArcSample> smp = measure.samples(run);
      auto command = [&](bool distance) {
        gm::ArcOffsets off{std::vector<double>(smp.size(), 0.0),
                           std::vector<double>(smp.size(), 0.0)};
        for (std::size_t i = 0; i < smp.size(); ++i) {
          if (!smp[i].on) continue;
          const auto o = rule.offset(1.0, smp[i].x, smp[i].s_mm / smp[i].advance_mm,
                                     (th - smp[i].s_mm) / smp[i].advance_mm, 1.0, 1.0, false,
                                     distance, distance);
          off.radial_mm[i] = o.radial_mm;
          off.along_mm[i] = o.along_mm;
        }
        return off;
      };
      const gm::ArcOffsets shared = command(false), distance = command(true);
      const double d_shared = measure.worst_fraction(run, shared);
      const double d_distance = measure.worst_fraction(run, distance);
      CAPTURE(frac, phase, d_shared, d_distance);
      CHECK(d_distance <= 0.071);
      CHECK(d_distance <= 0.65 * d_shared);
      CHECK(measure.worst_fraction(run, distance, gm::ArcEndMeasure::FromMean) > 0.3);
    }
}
