// The tool tip: a mode's ringing after a moving-average ramp in closed form, and the full-closed
// loop.
#include "servo/flexible_modes.hpp"
#include "servo/servo_axis.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <numbers>
#include <vector>

namespace {

// A velocity step V at t = 0 through a moving average of n taps at period T: the reference at
// sample j is (1/n)·Σ_{i<n} V·T·max(j − i, 0). Linear between samples (as FlexibleModes takes
// it), its velocity steps by V/n at t_k = k·T, k = 0..n−1.
double ma_ramp(double v, double period, int n, int j) {
  double s = 0.0;
  for (int i = 0; i < n; ++i) s += v * period * std::max(j - i, 0);
  return s / n;
}

}  // namespace

TEST_CASE("a ramp through a moving average: the tip rings as the sum of the velocity steps' rings",
          "[servo][modes][tip]") {
  // Undamped mode ω: a velocity step ΔV at t_k leaves the deflection e = y − x =
  // −(ΔV/ω)·sin(ω(t − t_k)); after the average (t ≥ n·T) e(t) = −(V/(nω))·Σ_k sin(ω(t − kT)),
  // of amplitude (V/(nω))·|sin(nωT/2) / sin(ωT/2)|.
  const double f = 40.0, w = 2 * std::numbers::pi * f, v = 100000.0, period = 0.001;
  for (const int n : {18, 25, 37, 60}) {
    gm::FlexibleModes m({f}, {0.0}, period, 0.0);
    double worst = 0.0, peak = 0.0;
    for (int j = 1; j <= 400; ++j) {
      const double x = ma_ramp(v, period, n, j), y = m.step(x), t = j * period;
      double hand = 0.0;
      for (int k = 0; k < std::min(j, n); ++k) hand -= v / n / w * std::sin(w * (t - k * period));
      worst = std::max(worst, std::abs((y - x) - hand));
      if (j >= n) peak = std::max(peak, std::abs(y - x));
    }
    const double amplitude =
        v / (n * w) * std::abs(std::sin(n * w * period / 2) / std::sin(w * period / 2));
    INFO("n = " << n);
    CHECK(worst < 1e-7);
    // 400 samples hold 14 periods of 40 Hz: the sampled crest is within 1.3 % of the amplitude.
    CHECK(peak <= amplitude * (1 + 1e-9) + 1e-9);
    CHECK(peak >= amplitude * 0.987);
  }
  // 60 taps (the ringing machine's linear profile, τ = 0.06 s): 12.6 % of the unshaped V/ω
  const double unshaped = v / w;
  const double a60 =
      v / (60 * w) * std::abs(std::sin(60 * w * period / 2) / std::sin(w * period / 2));
  // (undamped; V(f) of `gmotion analyze vibration` weighs the taps by the damping).
  CHECK(a60 / unshaped == Approx(0.12647).epsilon(1e-4));
}

TEST_CASE("a moving average of τ = 1/f leaves no residual vibration at the tip",
          "[servo][modes][tip]") {
  // n·T = 1/f: Σ_k e^{jωkT} over a whole turn is 0, so the rings of the n velocity steps cancel.
  // A move (accelerate, cruise, decelerate to rest) at V = 100 mm/s = 1e5 BLU/s: after the
  // average has come to rest the undamped 40 Hz tip stays within 1e-6 BLU of the end point, where
  // a single velocity step leaves V/ω = 398 BLU.
  const double f = 40.0, v = 100000.0, period = 0.001;
  const int n = 25;  // 25 ms = 1/40 Hz
  gm::FlexibleModes m({f}, {0.0}, period, 0.0);
  const int cruise = 290;  // samples at V before the stop of the interpolator output
  double residual = 0.0, during = 0.0, end = 0.0;
  for (int j = 1; j <= 1000; ++j) {
    // cmd: ramp for `cruise` samples, then at rest; ref: its moving average of n taps.
    double x = 0.0;
    for (int i = 0; i < n; ++i) x += v * period * std::clamp(j - i, 0, cruise);
    x /= n;
    const double y = m.step(x);
    if (j > n && j <= cruise) during = std::max(during, std::abs(y - x));  // cruising
    if (j >= n + cruise) residual = std::max(residual, std::abs(y - x)), end = x;
  }
  CHECK(end == Approx(v * period * cruise));
  CHECK(during < 1e-6);  // the start's rings cancel already
  CHECK(residual < 1e-6);
  // The same move through 37 taps (τ = 1.48/f) rings on: (V/(nω))·|sin(nωT/2)/sin(ωT/2)|.
  gm::FlexibleModes m2({f}, {0.0}, period, 0.0);
  const int n2 = 37;
  double residual2 = 0.0;
  for (int j = 1; j <= 1000; ++j) {
    double x = 0.0;
    for (int i = 0; i < n2; ++i) x += v * period * std::clamp(j - i, 0, cruise);
    x /= n2;
    const double y = m2.step(x);
    if (j >= n2 + cruise) residual2 = std::max(residual2, std::abs(y - x));
  }
  const double w = 2 * std::numbers::pi * f;
  // Start and stop rings add: two sums of n2 steps of opposite sign, the stop's `cruise`
  // samples later: one sum's amplitude times |1 − e^{−jω·cruise·T}| = 2|sin(ω·cruise·T/2)|
  // (11.6 periods: 1.902).
  const double one =
      v / (n2 * w) * std::abs(std::sin(n2 * w * period / 2) / std::sin(w * period / 2));
  const double both = one * 2 * std::abs(std::sin(w * cruise * period / 2));
  CHECK(both / one == Approx(1.902).epsilon(1e-3));
  CHECK(residual2 <= both * (1 + 1e-9));
  CHECK(residual2 >= both * 0.987);
  CHECK(residual2 > 100.0);
}

TEST_CASE("full-closed loop: the encoder on the table takes the lost motion out of the position",
          "[servo][encoder]") {
  // 200 BLU of backlash, a move of +5000 BLU ending in a hard stop (the motor overshoots a
  // little). Semi-closed (encoder on the motor) the motor ends at the reference and the table
  // where the motor dragged it: short by up to half the backlash (less what the overshoot
  // pushed it on). Full-closed the table ends within a count of the reference, the motor
  // anywhere inside the dead band around it.
  gm::AxisConfig semi;
  semi.backlash_blu = 200.0;
  gm::AxisConfig full = semi;
  full.encoder = gm::EncoderSite::Table;
  gm::ServoAxis a(semi, 0.004, 1, 0), b(full, 0.004, 1, 0);
  CHECK_FALSE(a.table_encoder());
  CHECK(b.table_encoder());
  std::int64_t ca = 0, cb = 0;
  for (int k = 0; k < 1500; ++k) {
    const std::int64_t ref = k < 50 ? 100 * k : 5000;
    ca = a.step(ref);
    cb = b.step(ref);
  }
  CHECK(std::llabs(ca - 5000) <= 1);
  CHECK(a.motor_blu() == Approx(5000).margin(1.0));
  CHECK(a.table_blu() >= 4900.0 - 1.0);
  CHECK(a.table_blu() < 4990.0);  // semi-closed: tens of BLU short
  CHECK(std::llabs(cb - 5000) <= 1);
  CHECK(b.table_blu() == Approx(5000).margin(1.0));
  CHECK(std::abs(b.motor_blu() - b.table_blu()) <= 100.0 + 1e-9);
}

TEST_CASE("full-closed loop with a mode: the position loop sees the ringing table",
          "[servo][encoder][modes]") {
  // A damped 40 Hz mode (ζ = 0.2): semi-closed, the encoder reads the motor and the counts are
  // those without the mode; full-closed the counts follow the table (they differ from the
  // motor's while it rings) and the table settles on the reference.
  gm::AxisConfig plain;
  plain.mode_hz = {40.0};
  plain.mode_damping = {0.2};
  gm::AxisConfig full = plain;
  full.encoder = gm::EncoderSite::Table;
  gm::ServoAxis semi(plain, 0.004, 1, 0), closed(full, 0.004, 1, 0);
  bool differ = false;
  double count_vs_table = 0.0;
  for (int k = 0; k < 1500; ++k) {
    const std::int64_t ref = k < 100 ? static_cast<std::int64_t>(std::llround(5.0 * k * k)) : 50000;
    const double table_before = closed.table_blu();
    const std::int64_t c = closed.step(ref);
    semi.step(ref);
    count_vs_table = std::max(count_vs_table, std::abs(static_cast<double>(c) - table_before));
    differ = differ || std::abs(closed.motor_blu() - semi.motor_blu()) > 1.0;
  }
  CHECK(count_vs_table <= 0.5);  // the count read is the table's position rounded
  CHECK(differ);                 // the loop reacts to the mode: the motor moves otherwise
  CHECK(closed.table_blu() == Approx(50000).margin(1.0));
  CHECK(semi.table_blu() == Approx(50000).margin(1.0));
}
