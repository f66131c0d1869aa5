// Structural modes between motor and table: FlexibleModes against closed forms, in ServoAxis.
#include "servo/flexible_modes.hpp"
#include "servo/servo_axis.hpp"

#include "common/status.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

namespace {
constexpr double kPi = std::numbers::pi;
}

TEST_CASE("an undamped 40 Hz mode excited by a velocity step rings at 40 Hz, amplitude V/ω",
          "[servo][modes]") {
  // The motor starts at V = 50000 BLU/s from rest at t = 0: x = V t. The table, ÿ = ω² (x − y)
  // from rest, is y = V t − (V/ω) sin ωt: it rings about the motor at 40 Hz with amplitude
  // V/ω = 198.9 BLU. Exact for an input linear over each period (here it is).
  const double f = 40.0, w = 2 * kPi * f, v = 50000.0, h = 0.001;
  gm::FlexibleModes m({f}, {0.0}, h, 0.0);
  double worst = 0.0, peak = 0.0;
  for (int k = 1; k <= 200; ++k) {
    const double t = k * h, y = m.step(v * t);
    const double hand = v * t - v / w * std::sin(w * t);
    worst = std::max(worst, std::abs(y - hand));
    peak = std::max(peak, std::abs(y - v * t));
  }
  CHECK(worst < 1e-8);
  CHECK(v / w == Approx(198.94).epsilon(1e-4));
  CHECK(peak == Approx(v / w).epsilon(0.01));  // sampled every 1 ms: within 1 % of the crest
}

TEST_CASE("an undamped 40 Hz mode after a position step of one servo period: A·sinc(ωh/2)",
          "[servo][modes]") {
  // The input goes from 0 to A within one period h (linearly) and stays: for t ≥ h,
  // y = A − (2A/(ωh))·sin(ωh/2)·cos(ω(t − h/2)).
  const double f = 40.0, w = 2 * kPi * f, a = 1000.0, h = 0.004;
  gm::FlexibleModes m({f}, {0.0}, h, 0.0);
  double worst = 0.0;
  for (int k = 1; k <= 100; ++k) {
    const double t = k * h, y = m.step(a);
    const double hand = a - 2 * a / (w * h) * std::sin(w * h / 2) * std::cos(w * (t - h / 2));
    worst = std::max(worst, std::abs(y - hand));
  }
  CHECK(worst < 1e-9 * a);
  // Damped (ζ = 0.05), free after the step: the ringing falls by e^{−ζω·Td} over one damped
  // period Td = 1/(f·√(1 − ζ²)); sampled five times a period, y[k + 5] = e^{−ζω·Td}·y[k].
  const double z = 0.05, td = 1.0 / (40.0 * std::sqrt(1 - z * z));
  gm::FlexibleModes d({40.0}, {z}, td / 5, 0.0);
  std::vector<double> y;
  for (int k = 0; k < 40; ++k) y.push_back(d.step(a) - a);
  CHECK(y[25] / y[20] == Approx(std::exp(-z * w * td)).epsilon(1e-9));
  CHECK(y[35] / y[20] == Approx(std::exp(-3 * z * w * td)).epsilon(1e-9));
}

TEST_CASE("ServoAxis with a mode: the encoder stays on the motor, the table rings",
          "[servo][modes]") {
  gm::AxisConfig plain;  // the paper's x (defaults)
  gm::AxisConfig flex = plain;
  flex.mode_hz = {40.0};
  flex.mode_damping = {0.0};
  gm::ServoAxis a(plain, 0.004, 4, 0), b(flex, 0.004, 4, 0);
  CHECK(b.has_modes());
  CHECK_FALSE(a.has_modes());
  double ring = 0.0;
  std::int64_t ref = 0;
  for (int k = 0; k < 400; ++k) {
    ref = k < 100 ? static_cast<std::int64_t>(std::llround(20.0 * k * k)) : ref;  // a hard stop
    CHECK(a.step(ref) == b.step(ref));  // semi-closed: the loop never sees the mode
    CHECK(a.motor_blu() == b.motor_blu());
    if (k > 300) ring = std::max(ring, std::abs(b.table_blu() - b.motor_blu()));
  }
  CHECK(a.table_blu() == a.motor_blu());
  CHECK(ring > 1.0);  // undamped: still ringing 0.8 s after the stop
  gm::AxisConfig bad = flex;
  bad.mode_damping = {};
  CHECK_THROWS_AS(gm::ServoAxis(bad, 0.004, 1, 0), gm::InputError);
  bad = flex;
  bad.mode_hz = {-1.0};
  CHECK_THROWS_AS(gm::ServoAxis(bad, 0.004, 1, 0), gm::InputError);
}
