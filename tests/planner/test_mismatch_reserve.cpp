// The servo-mismatch reserve: its value at a speed, the speed where a load reaches a share beside
// it, and an isolated corner's cap against the closed form share/(D(P)·|Δu| + M).
#include "accdec/taps.hpp"
#include "interp/program.hpp"
#include "machine/machine.hpp"
#include "planner/filter_moments.hpp"
#include "planner/mismatch_reserve.hpp"
#include "planner/tolerance_planner.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>
#include <variant>

TEST_CASE("mismatch reserve: M times the speed, at most M times the fastest within reach") {
  const gm::MismatchReserve r{2e-5, 150.0, 0.004};
  CHECK(r.at(100.0, true) == Approx(0.002).epsilon(1e-14));   // capped at 100 mm/s: M·100
  CHECK(r.at(200.0, true) == Approx(0.003).epsilon(1e-14));   // no faster than within reach
  CHECK(r.at(100.0, false) == Approx(0.003).epsilon(1e-14));  // uncapped: the fastest in reach
  CHECK(r.ceiling_mm() == Approx(0.003).epsilon(1e-14));
  const gm::MismatchReserve low{2e-5, 150.0, 0.0025};  // reserve_of(tol) below M·150
  CHECK(low.at(200.0, false) == 0.0025);
  CHECK(low.at(100.0, true) == Approx(0.002).epsilon(1e-14));
  const gm::MismatchReserve none{0.0, 0.0, 0.0};  // no mismatch
  CHECK(none.at(500.0, false) == 0.0);
  CHECK(none.at(500.0, true) == 0.0);
}

TEST_CASE("mismatch reserve: where a load reaches the share beside it") {
  const gm::MismatchReserve r{2e-5, 150.0, 0.004};
  // A corner's load b·v: b·v + M·v = c while M·v stays under M·150.
  // v = 0.005 / (0.01 + 2e-5) = 0.499002 mm/s.
  CHECK(r.root(0.0, 0.01, 0.005) == Approx(0.005 / 0.01002).epsilon(1e-14));
  // A light load: b·v + M·v = c would need v = 166.7 mm/s, past the reach (M·v > 0.003), so
  // the reserve is 0.003 and b·v = 0.002: v = 200 mm/s.
  CHECK(r.root(0.0, 1e-5, 0.005) == Approx(200.0).epsilon(1e-12));
  // An arc's a·v² with a = 1e-6: a·v² + M·v = 0.004, v = (−M + √(M² + 4·a·c))/(2a) = 54.0312.
  const double v = r.root(1e-6, 0.0, 0.004);
  CHECK(v == Approx((-2e-5 + std::sqrt(4e-10 + 1.6e-8)) / 2e-6).epsilon(1e-12));
  CHECK(1e-6 * v * v + r.at(v, true) == Approx(0.004).epsilon(1e-12));
  // Without a mismatch the plain roots: c/b and √(c/a).
  const gm::MismatchReserve none;
  CHECK(none.root(0.0, 0.01, 0.005) == 0.5);
  CHECK(none.root(1e-6, 0.0, 0.004) == Approx(std::sqrt(0.004 / 1e-6)).epsilon(1e-14));
}

TEST_CASE("a capped corner keeps M times its own cap for the mismatch, not half its share") {
  // One 90° corner between two 40 mm lines at F3000 (100 mm/s at 200 %), the linear profile
  // τ 0.1 s, G64 P0.01, a servo mismatch M = 2·10⁻⁵ s. Its samples' windows lie in its zone, so
  // the cap v and pause P satisfy v·D(P)·|Δu| + M·v = share: v = share/(D(P)·√2 + M). The rule
  // before kept min(share/2, V_rapid·M) = 0.004 mm whatever the cap.
  gm::Machine m;
  m.profile = "linear";
  m.tau_s = 0.1;
  gm::PlannerConfig pc;
  pc.max_override = m.max_override;
  pc.rapid_mm_min = m.rapid_mm_min;
  pc.rounding_mm = 0.001 * std::sqrt(3.0);
  pc.speed_error_s = 2e-5;
  const gm::FilterMoments fm(gm::design_taps(m.profile, m.tau_s, m.period_s), m.period_s);
  std::istringstream in("G21 G90 G17 G64 P0.01\nG1 X40 F3000\nG1 Y40\nM2\n");
  gm::InterpreterOptions opts;
  opts.machine = &m;
  gm::ProgramStream stream(in, "corner.nc", opts);
  gm::TolerancePlanner planner(fm, pc, stream);
  double cap = 0.0, pause = 0.0;
  int capped = 0;
  gm::Canon c;
  while (planner.next(c)) {
    if (const auto* mo = std::get_if<gm::Motion>(&c); mo != nullptr && mo->speed_cap_mm_s > 0.0) {
      CHECK((cap == 0.0 || mo->speed_cap_mm_s == cap));  // one cap, both sides of the corner
      cap = mo->speed_cap_mm_s;
      ++capped;
    }
    if (const auto* d = std::get_if<gm::Dwell>(&c)) pause += d->seconds;
  }
  REQUIRE(capped == 2);
  const double share = 0.01 - pc.rounding_mm;
  const double d = fm.corner_moment_s(pause);
  CAPTURE(pause, d, cap);
  CHECK(cap == Approx(share / (d * std::sqrt(2.0) + pc.speed_error_s)).epsilon(1e-9));
  // The rule before, at the same pause: (share − 0.004)/(D(P)·√2) = 37.7 mm/s.
  CHECK(cap > 1.6 * (share - 0.004) / (d * std::sqrt(2.0)));
}
