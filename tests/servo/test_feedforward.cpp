// Velocity and acceleration feedforward (ff1, ff2_s) against the loop's steady states by hand.
#include "servo/servo_axis.hpp"

#include "common/status.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>

using gm::AxisConfig;
using gm::ServoAxis;

namespace {

constexpr double kFfPeriodS = 0.004;

// The paper's x axis, written out (independently of the defaults).
AxisConfig paper_x(double ff1, double ff2_s) {
  AxisConfig a;
  a.blu_mm = 0.001;
  a.mass_kg = 500.0;
  a.f_max_N = 4000.0;
  a.kp_1_s = 30.0;
  a.plant_blu_s_per_unit = 34000.0;
  a.kv_period_s = 0.004;
  a.kv_form = gm::VelocityLoopForm::Ip;
  a.plant_num = {33.518};
  a.plant_den = {1.0, 14.45};
  a.kvp = 0.0422;
  a.kvi = 0.0094;
  a.ff1 = ff1;
  a.ff2_s = ff2_s;
  return a;
}

// Mean, min and max of ref − count over samples n0 .. n0+n−1 for the reference ref(k).
struct Following {
  double mean = 0.0, lo = 1e300, hi = -1e300;
};
template <class Ref>
Following following(const AxisConfig& ax, int substeps, Ref ref, int n0, int n) {
  ServoAxis s(ax, kFfPeriodS, substeps, 0);
  Following f;
  for (int k = 0; k < n0 + n; ++k) {
    const std::int64_t r = ref(k);
    const double e = static_cast<double>(r - s.step(r));
    if (k < n0) continue;
    f.mean += e / n;
    f.lo = std::min(f.lo, e);
    f.hi = std::max(f.hi, e);
  }
  return f;
}

}  // namespace

TEST_CASE("velocity feedforward: the ramp's following error is (1 − ff1)·V/Kp", "[servo][ff]") {
  // At constant velocity V the velocity loop's integral makes the velocity command equal the
  // measured velocity V on average: Kp·e + ff1·V = V (ff2_s sees no acceleration).
  for (int substeps : {1, 4})
    for (double ff1 : {0.0, 0.5, 0.857, 1.0})
      for (double ff2 : {0.0, 0.0143}) {
        const double v = 15000.0;  // 60 BLU per period
        const Following f = following(
            paper_x(ff1, ff2), substeps, [&](int k) { return std::llround(v * k * kFfPeriodS); },
            500, 500);
        const double expected = (1.0 - ff1) * v / 30.0;
        CAPTURE(substeps, ff1, ff2, f.mean, f.lo, f.hi, expected);
        CHECK(f.mean == Approx(expected).margin(0.5));
        CHECK(f.lo >= expected - 2.0);
        CHECK(f.hi <= expected + 2.0);
      }
}

TEST_CASE("acceleration feedforward: with ff1 = 1 a parabola's error is A·(c1 − ff2)/Kp",
          "[servo][ff]") {
  // ref_k = k² BLU: constant acceleration A = 2/T² = 125000 BLU/s². In the steady state the
  // position lags by a constant e, the velocity feedback y_k = (2k − 1)·kv/T and, with ff1 = 1,
  // the velocity command minus y is the constant (Kp·e + ff2·A)·kv. So the integral grows by
  // (Kp·e + ff2·A)·T a sample and u = Kvi·I − Kvp·y by Kvi·(Kp·e + ff2·A)·T − Kvp·kv·A·T. A plant
  // b/(s + a) whose velocity grows by A·T a sample needs u to grow by A·T·a/g (g = b · BLU/s
  // per unit). Equal: e = A·(c1 − ff2)/Kp, c1 = (a/g + Kvp·kv)/Kvi — the velocity loop's ramp
  // lag, 2ζ/ωn of the continuous loop (docs/servo.md: 19.3 ms).
  const double a = 14.45, g = 33.518 * 34000.0, c1 = (a / g + 0.0422 * 0.004) / 0.0094;
  CHECK(c1 == Approx(0.019306).epsilon(1e-4));
  const double acc = 2.0 / (kFfPeriodS * kFfPeriodS);
  for (double ff2 : {0.0, c1 / 2, c1, 0.0143}) {
    // 400 samples: 200000 BLU/s at the end, the drive well inside its limit.
    const Following f = following(
        paper_x(1.0, ff2), 1, [](int k) { return static_cast<std::int64_t>(k) * k; }, 250, 150);
    const double expected = acc * (c1 - ff2) / 30.0;  // 80.45 BLU at ff2 = 0
    CAPTURE(ff2, f.mean, f.lo, f.hi, expected);
    std::printf("parabola A=%.0f BLU/s2 ff1=1 ff2=%.4f s: following error mean %.3f (hand %.3f)\n",
                acc, ff2, f.mean, expected);
    CHECK(f.mean == Approx(expected).margin(0.5));
    CHECK(f.hi - f.lo <= 3.0);
  }
}

TEST_CASE("feedforward gains in the velocity loop's units", "[servo][ff]") {
  // ff1·(ref[k] − ref[k−1])/T BLU/s in counts per kv_period_s: ff1·kv/T per BLU of difference;
  // ff2_s·(Δref[k] − Δref[k−1])/T² likewise.
  const ServoAxis s(paper_x(0.857, 0.0143), kFfPeriodS, 4, 0);
  CHECK(s.ff1_gain() == Approx(0.857 * 0.004 / 0.004));
  CHECK(s.ff2_gain() == Approx(0.0143 * 0.004 / (0.004 * 0.004)));
  const ServoAxis t(paper_x(1.0, 0.0), 0.001, 1, 0);  // T = 1 ms, kv_period_s 4 ms
  CHECK(t.ff1_gain() == Approx(4.0));
  CHECK(t.ff2_gain() == 0.0);
  AxisConfig bad = paper_x(std::nan(""), 0.0);
  CHECK_THROWS_AS(ServoAxis(bad, kFfPeriodS, 1, 0), gm::InputError);
}
