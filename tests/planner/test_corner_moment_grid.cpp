// The grid of corner moments against FilterMoments::corner_moment_s, bit for bit, on FIR and
// FIR + servo chains with and without overshoot.
#include "accdec/taps.hpp"
#include "machine/machine.hpp"
#include "planner/corner_moment_grid.hpp"
#include "planner/filter_moments.hpp"
#include "planner/servo_response.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

namespace {

std::uint64_t bits(double x) {
  return std::bit_cast<std::uint64_t>(x);
}

// The table as the planner built it before the grid: FilterMoments::corner_moment_s as it stood
// then, word for word, a bisection of up to 200 mids, each comparing sums over all the weights.
struct ReferenceMoments {
  std::vector<double> h;
  double T, over_s, under_s;
  explicit ReferenceMoments(const gm::FilterMoments& f)
      : h(f.weights()), T(f.period_s()), over_s(f.overshoot_s()), under_s(f.undershoot_s()) {}
  double tau_s() const { return T * static_cast<double>(h.size()); }
  double pre_moment(double t) const {
    double a = 0.0;
    for (std::size_t i = 0; i < h.size(); ++i)
      a += h[i] * std::max(static_cast<double>(i) * T - t, 0.0);
    return a;
  }
  double post_moment(double t) const {
    double b = 0.0;
    for (std::size_t i = 0; i < h.size(); ++i)
      b += h[i] * std::max(t - static_cast<double>(i) * T, 0.0);
    return b;
  }
  double pre_pos(double t) const {
    double a = 0.0, c = 1.0;
    for (std::size_t k = 0; k < h.size(); ++k) {
      const double hi = static_cast<double>(k) * T, lo = hi - T;
      a += std::max(c, 0.0) * std::clamp(hi - std::max(t, lo), 0.0, T);
      c -= h[k];
    }
    return a;
  }
  double post_pos(double t) const {
    double b = 0.0, s = 0.0;
    for (std::size_t k = 0; k < h.size(); ++k) {
      s += h[k];
      const double lo = static_cast<double>(k) * T, hi = lo + T;
      if (k + 1 == h.size()) return b + std::max(s, 0.0) * std::max(t - lo, 0.0);
      b += std::max(s, 0.0) * std::clamp(std::min(t, hi) - lo, 0.0, T);
    }
    return b;
  }
  double corner_moment_s(double pause_s) const {
    if (over_s > 0.0 || under_s > 0.0) {
      double lo = -T, hi = tau_s() + pause_s + T;
      for (int it = 0; it < 200 && hi - lo > 1e-15 * (1.0 + hi); ++it) {
        const double mid = 0.5 * (lo + hi);
        (pre_pos(mid) > post_pos(mid - pause_s) ? lo : hi) = mid;
      }
      const double t = 0.5 * (lo + hi);
      const double d = std::max(0.0, std::min(pre_pos(t), post_pos(t - pause_s)));
      return std::max({d, over_s, under_s});
    }
    double lo = -T, hi = tau_s() + pause_s + T;
    for (int it = 0; it < 200 && hi - lo > 1e-15 * (1.0 + hi); ++it) {
      const double mid = 0.5 * (lo + hi);
      if (pre_moment(mid) > post_moment(mid - pause_s))
        lo = mid;
      else
        hi = mid;
    }
    const double t = 0.5 * (lo + hi);
    return std::max(0.0, std::min(pre_moment(t), post_moment(t - pause_s)));
  }
};

// Every grid entry in steps of `stride` (and the last), and the grid's bisection at pauses off
// the grid (half samples and a step of 1.3 ms), against the reference's bisection.
void check_grid(const gm::FilterMoments& f, int stride) {
  gm::CornerMomentGrid grid(f);
  const ReferenceMoments ref(f);
  REQUIRE(grid.size() == f.order() + 1);
  const double T = f.period_s();
  int checked = 0;
  std::vector<int> js;
  for (int j = 0; j < grid.size(); j += stride) js.push_back(j);
  if (js.back() != grid.size() - 1) js.push_back(grid.size() - 1);
  for (int j : js) {
    const double reference = ref.corner_moment_s(0.5 * (2 * j) * T);
    INFO("j = " << j << " of " << grid.size() - 1);
    CHECK(bits(grid.at(j)) == bits(reference));
    CHECK(bits(grid.at(j)) == bits(reference));  // a second ask returns the kept value
    ++checked;
  }
  CHECK(checked >= 2);
  for (double p : {0.5 * T, 1.5 * T, 0.0013, 0.0131, 0.5 * f.tau_s() + 0.5 * T, f.tau_s()}) {
    INFO("pause " << p);
    CHECK(bits(grid.moment_s(p)) == bits(ref.corner_moment_s(p)));
  }
}

}  // namespace

TEST_CASE("corner moment grid: FIR taps, bit for bit as the bisection over all weights") {
  for (const char* prof : {"linear", "blackman", "hann", "scurve1"})
    for (double tau : {0.084, 0.1, 0.164}) {
      INFO(prof << " tau " << tau);
      const gm::Taps taps = gm::design_taps(prof, tau, 0.004);
      const gm::FilterMoments f(taps, 0.004);
      check_grid(f, 1);
    }
  // Moving average of 25 taps: D(0) = T·78/25 and D(2T) = T·66/25 by hand (test_filter_moments).
  const gm::FilterMoments lin(gm::design_taps("linear", 0.1, 0.004), 0.004);
  gm::CornerMomentGrid grid(lin);
  CHECK(grid.at(0) == Approx(0.004 * 78.0 / 25.0).epsilon(1e-9));
  CHECK(grid.at(2) == Approx(0.004 * 66.0 / 25.0).epsilon(1e-9));
  CHECK(grid.at(grid.size() - 1) == 0.0);  // D(N·T) = 0
}

TEST_CASE("corner moment grid: negative weights whose step response stays in [0, 1]") {
  // S = 0.3, 0.8, 0.7, 1: no overshoot, so A and B are the plain moments with a negative term.
  const gm::FilterMoments small({0.3, 0.5, -0.1, 0.3}, 0.5);
  REQUIRE(small.overshoot_s() == 0.0);
  REQUIRE(small.undershoot_s() == 0.0);
  check_grid(small, 1);
  // A long one: a smooth ramp of 600 weights with a small negative ripple.
  std::vector<double> w(600);
  double sum = 0.0;
  for (std::size_t k = 0; k < w.size(); ++k) {
    w[k] = 1.0 + 0.9 * std::sin(0.37 * static_cast<double>(k));
    sum += w[k];
  }
  for (double& x : w) x /= sum;
  w[5] -= 0.0004, w[6] += 0.0004;
  const gm::FilterMoments ramp(w, 0.001);
  REQUIRE(ramp.overshoot_s() == 0.0);
  check_grid(ramp, 1);
}

TEST_CASE("corner moment grid: FIR + servo chains that overshoot (the encoder plan)") {
  gm::Machine m;
  m.tolerance_on = gm::ToleranceOn::Encoder;
  m.servo_matching = false;  // the loop unshaped: its chain overshoots
  const gm::FilterMoments chain(gm::plan_chain(m, true).weights, m.period_s);
  REQUIRE(chain.overshoot_s() > 0.0);
  check_grid(chain, 1);

  // A 20 Hz structural mode at damping 0.05, T = 1 ms: 1,344 weights. Every 37th pause.
  gm::Machine ringing;
  ringing.tolerance_on = gm::ToleranceOn::Encoder;
  ringing.period_s = 0.001;
  for (gm::AxisConfig& a : ringing.axes) {
    a.mode_hz = {20.0};
    a.mode_damping = {0.05};
  }
  const gm::FilterMoments mode(gm::plan_chain(ringing, true).weights, ringing.period_s);
  CHECK(mode.weights().size() > 1000);
  check_grid(mode, 37);

  // A decaying oscillation of 5,000 weights (test_filter_moments "signed weights"): every 211th.
  std::vector<double> w(5000);
  double rest = 1.0;
  for (std::size_t k = 1; k < w.size(); ++k) {
    w[k] =
        0.01 * std::exp(-static_cast<double>(k) / 800.0) * std::cos(static_cast<double>(k) * 0.05);
    rest -= w[k];
  }
  w[0] = rest;
  const gm::FilterMoments ring(w, 0.001);
  REQUIRE(ring.overshoot_s() + ring.undershoot_s() > 0.0);
  check_grid(ring, 211);
}
