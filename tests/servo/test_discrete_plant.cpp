// Exact ZOH discretisation checked against hand-computed closed forms.
#include "servo/discrete_plant.hpp"

#include "common/status.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using gm::DiscretePlant;

TEST_CASE("first-order plant b/(s+a): ZOH matrices equal e^{-aT} closed forms", "[servo][plant]") {
  const double a = 14.45, b = 33.518, scale = 34000.0, h = 0.004;
  DiscretePlant p({b}, {1.0, a}, scale, h);
  REQUIRE(p.order() == 1);
  const double e = std::exp(-a * h);
  // State x (plant input units integrated), v = b*scale*x, position p' = v.
  CHECK(p.ad()(0, 0) == Approx(e).epsilon(1e-12));
  CHECK(p.bd()[0] == Approx((1.0 - e) / a).epsilon(1e-12));
  CHECK(p.ad()(1, 0) == Approx(b * scale * (1.0 - e) / a).epsilon(1e-12));
  CHECK(p.ad()(1, 1) == Approx(1.0).epsilon(1e-15));
  CHECK(p.ad()(0, 1) == 0.0);
  CHECK(p.bd()[1] == Approx(b * scale / a * (h - (1.0 - e) / a)).epsilon(1e-10));
  CHECK(p.dc_gain_blu_s() == Approx(b / a * scale));
  CHECK(p.accel_gain_blu_s2() == Approx(b * scale));

  // Unit step for k samples: v = (b s/a)(1 - e^{-a t}), position = (b s/a)(t - (1-e^{-a t})/a).
  for (int k = 0; k < 50; ++k) p.step(1.0);
  const double t = 50 * h;
  CHECK(p.velocity_blu_s() == Approx(b * scale / a * (1.0 - std::exp(-a * t))).epsilon(1e-11));
  CHECK(p.position_blu() ==
        Approx(b * scale / a * (t - (1.0 - std::exp(-a * t)) / a)).epsilon(1e-10));
}

TEST_CASE("second-order plant 2/(s^2+3s+2): step response equals the analytic one",
          "[servo][plant]") {
  // G = 2/((s+1)(s+2)); unit step: v = 1 - 2e^{-t} + e^{-2t}; position = t - 1.5 + 2e^{-t} -
  // e^{-2t}/2.
  DiscretePlant p({2.0}, {1.0, 3.0, 2.0}, 1.0, 0.01);
  REQUIRE(p.order() == 2);
  CHECK(p.accel_gain_blu_s2() == 0.0);  // relative degree 2
  for (int k = 1; k <= 300; ++k) {
    p.step(1.0);
    const double t = 0.01 * k;
    INFO("t = " << t);
    CHECK(p.velocity_blu_s() ==
          Approx(1.0 - 2.0 * std::exp(-t) + std::exp(-2.0 * t)).margin(1e-12));
    CHECK(p.position_blu() ==
          Approx(t - 1.5 + 2.0 * std::exp(-t) - 0.5 * std::exp(-2.0 * t)).margin(1e-11));
  }
}

TEST_CASE("numerator with a zero (s+3)/(s^2+3s+2) and leading zeros in num", "[servo][plant]") {
  // (s+3)/((s+1)(s+2)): unit step v = 1.5 - 2e^{-t} + 0.5e^{-2t}.
  DiscretePlant p({0.0, 1.0, 3.0}, {1.0, 3.0, 2.0}, 1.0, 0.02);
  CHECK(p.accel_gain_blu_s2() == Approx(1.0));
  for (int k = 1; k <= 100; ++k) p.step(1.0);
  const double t = 2.0;
  CHECK(p.velocity_blu_s() ==
        Approx(1.5 - 2.0 * std::exp(-t) + 0.5 * std::exp(-2.0 * t)).margin(1e-12));
}

TEST_CASE("invalid plants are rejected", "[servo][plant]") {
  CHECK_THROWS_AS(DiscretePlant({1.0}, {0.0, 1.0}, 1.0, 0.004), gm::InputError);  // den[0] = 0
  CHECK_THROWS_AS(DiscretePlant({1.0, 1.0}, {1.0, 2.0}, 1.0, 0.004),
                  gm::InputError);                                           // not strictly proper
  CHECK_THROWS_AS(DiscretePlant({1.0}, {1.0}, 1.0, 0.004), gm::InputError);  // order 0
  CHECK_THROWS_AS(DiscretePlant({0.0}, {1.0, 2.0}, 1.0, 0.004), gm::InputError);   // zero numerator
  CHECK_THROWS_AS(DiscretePlant({1.0}, {1.0, 2.0}, 1.0, 0.0), gm::InputError);     // period 0
  CHECK_THROWS_AS(DiscretePlant({1.0}, {1.0, 2.0}, -1.0, 0.004), gm::InputError);  // scale < 0
}
