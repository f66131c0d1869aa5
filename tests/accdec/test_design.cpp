// Fig. 9 design procedure and the design/analyze CLI (section 6 example, closed-form tau growth).
#include "accdec/design_procedure.hpp"
#include "accdec/taps.hpp"

#include "support/run_command.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

using gmtest::run_gmotion;

TEST_CASE(
    "section 6 example: Blackman N = 40 passes Step 4 at the first tau, Eq. 7 with its taps") {
  const gm::DesignLimits lim;  // paper defaults
  const auto attempts = gm::design_procedure("blackman", 0.164, 0.004, lim);
  REQUIRE(attempts.size() == 1);
  const auto& a = attempts.back();
  CHECK(a.ok());
  CHECK(a.taps.N == 40);
  // Eq. 7 from the applied integer taps, computed here.
  const double bmax =
      static_cast<double>(*std::max_element(a.taps.integer.begin(), a.taps.integer.end()));
  const double acc = 0.1 * bmax / (0.004 * static_cast<double>(a.taps.b_s));
  CHECK(a.peak_accel_m_s2 == Approx(acc).epsilon(1e-14));
  CHECK(a.peak_force_N == Approx(500 * acc + 500 * 0.1).epsilon(1e-14));
  CHECK(a.peak_power_W == Approx((500 * acc + 500 * 0.1) * 0.1).epsilon(1e-14));
  // The real Blackman peak tap (0.0692894) gives 1.732 m/s², not the paper's 7 m/s².
  CHECK(acc == Approx(1.7322).margin(1e-3));
  CHECK(a.profile_force_N <= a.peak_force_N);
}

TEST_CASE(
    "Fig. 9 loop: linear, F_max 1050 N -> tau grows by T until 12500/n + 50 <= 1050 (n = 13)") {
  gm::DesignLimits lim;
  lim.f_max_N = 1050;  // F = m·V/(nT) + cV = 500·0.1/(0.004 n) + 50 = 12500/n + 50
  const auto attempts = gm::design_procedure("linear", 0.02, 0.004, lim);
  REQUIRE(attempts.size() == 9);  // n = 5 .. 13
  for (std::size_t i = 0; i + 1 < attempts.size(); ++i) CHECK_FALSE(attempts[i].ok());
  CHECK(attempts.back().ok());
  CHECK(attempts.back().taps.N + 1 == 13);
  CHECK(attempts.back().tau_s == Approx(0.052).epsilon(1e-12));
  CHECK(attempts.back().peak_force_N == Approx(12500.0 / 13 + 50).epsilon(1e-12));
  // A fixed-length profile cannot grow: one attempt, not ok.
  const auto fixed = gm::design_procedure("custom:0.5,1,2,1,0.5", 0.02, 0.004, lim);
  CHECK(fixed.size() == 1);
  CHECK_FALSE(fixed.back().ok());
}

TEST_CASE("gmotion design --json prints the required keys for the section 6 defaults") {
  const auto r = run_gmotion("design --json");
  CHECK(r.code == 0);
  for (const char* key : {"\"N\":40", "\"cutoff\":0.04878048780487", "\"taps\":[", "\"taps_int\":[",
                          "\"b_s\":", "\"peak_accel\":1.73", "\"peak_force\":916.1",
                          "\"peak_power\":91.6", "\"tau\":0.164", "\"ok\":true"}) {
    INFO(key);
    CHECK(r.out.find(key) != std::string::npos);
  }
  const auto tight = run_gmotion("design --profile linear --tau 0.02 --fmax 1050");
  CHECK(tight.code == 0);
  CHECK(tight.out.find("0.052") != std::string::npos);
  const auto impossible = run_gmotion("design --profile custom:0.5,1,2,1,0.5 --fmax 1050");
  CHECK(impossible.code == 1);
}

TEST_CASE(
    "gmotion analyze: radius-error rows and response CSV, bad profiles exit 1 with a message") {
  const auto r = run_gmotion("analyze radius-error --feeds 6000,30000 --json");
  CHECK(r.code == 0);
  CHECK(r.out.find("{\"feed_mm_min\":6000,\"sampled_um\":4.666") != std::string::npos);
  CHECK(r.out.find("\"continuous_um\":4.66940083721") != std::string::npos);
  CHECK(r.out.find("\"approx_um\":116.7361111") != std::string::npos);
  const auto nl = run_gmotion(
      "analyze radius-error --profile blackman --tau 0.164 --period 0.004 "
      "--radius 4 --feeds 900 --json");
  CHECK(nl.code == 0);
  CHECK(nl.out.find("continuous_um") == std::string::npos);
  const auto csv =
      run_gmotion("analyze response --profile linear --tau 0.02 --period 0.004 --points 3");
  CHECK(csv.code == 0);
  // f_norm 0.5 -> ωT = π/2: |sin(5π/4)/(5 sin(π/4))| = 0.2
  CHECK(csv.out.find("\n0.5,62.5,1.5707963,0.2") != std::string::npos);
  const auto neg = run_gmotion("design --profile custom:1,-2,1");
  CHECK(neg.code == 1);
  CHECK(neg.out.find("b1") != std::string::npos);
  const auto frac = run_gmotion("analyze radius-error --tau 0.041 --period 0.004");
  CHECK(frac.code == 1);
  CHECK(frac.out.find("10.25") != std::string::npos);
}
