// identify_loop and zpetc_weights on hand-made loops: the transfer function recovered from the
// step response, and the zero-phase-error taps worked by hand.
#include "planner/loop_shaping.hpp"

#include <catch2/catch.hpp>

#include <vector>

namespace {

// The step response of y_k = 1.5·y_{k−1} − 0.56·y_{k−2} + 0.04·u_{k−1} + 0.02·u_{k−2} (poles 0.7
// and 0.8, one sample of delay, a zero at −0.5, unit gain: B(1) = A(1) = 0.06), by its
// recurrence; `u` the input (a unit step when empty).
std::vector<double> second_order(int n, const std::vector<double>& u = {}) {
  const auto in = [&u](int k) {
    if (k < 0) return 0.0;
    return u.empty() ? 1.0 : k < static_cast<int>(u.size()) ? u[static_cast<std::size_t>(k)] : 1.0;
  };
  std::vector<double> y(static_cast<std::size_t>(n), 0.0);
  for (int k = 0; k < n; ++k) {
    const double y1 = k >= 1 ? y[static_cast<std::size_t>(k - 1)] : 0.0;
    const double y2 = k >= 2 ? y[static_cast<std::size_t>(k - 2)] : 0.0;
    y[static_cast<std::size_t>(k)] = 1.5 * y1 - 0.56 * y2 + 0.04 * in(k - 1) + 0.02 * in(k - 2);
  }
  return y;
}

}  // namespace

TEST_CASE("identify_loop: a second-order loop's B/A from its step response") {
  const gm::LoopModel loop = gm::identify_loop(second_order(4096));
  REQUIRE(loop.a.size() == 3);  // the least order that reproduces it: 2
  CHECK(loop.a[0] == 1.0);
  CHECK(loop.a[1] == Approx(-1.5).margin(1e-12));
  CHECK(loop.a[2] == Approx(0.56).margin(1e-12));
  REQUIRE(loop.b.size() == 3);
  CHECK(loop.b[0] == Approx(0.0).margin(1e-14));
  CHECK(loop.b[1] == Approx(0.04).margin(1e-12));
  CHECK(loop.b[2] == Approx(0.02).margin(1e-12));
}

TEST_CASE("zpetc_weights: worked by hand, and the loop then settles in three samples") {
  // F = A(z)·B̃(z)/B(1)² with B̃ = 0.02 + 0.04·z⁻¹ (B after its delay, reversed):
  // (1 − 1.5z⁻¹ + 0.56z⁻²)(0.02 + 0.04z⁻¹) = 0.02 + 0.01z⁻¹ − 0.0488z⁻² + 0.0224z⁻³, / 0.0036.
  const gm::LoopModel loop{{1.0, -1.5, 0.56}, {0.0, 0.04, 0.02}};
  const std::vector<double> f = gm::zpetc_weights(loop);
  REQUIRE(f.size() == 4);
  CHECK(f[0] == Approx(0.02 / 0.0036).epsilon(1e-12));
  CHECK(f[1] == Approx(0.01 / 0.0036).epsilon(1e-12));
  CHECK(f[2] == Approx(-0.0488 / 0.0036).epsilon(1e-12));
  CHECK(f[3] == Approx(0.0224 / 0.0036).epsilon(1e-12));
  // The loop on a step through F follows z⁻¹·(0.04 + 0.02z⁻¹)(0.02 + 0.04z⁻¹)/0.0036 =
  // z⁻¹·(0.0008 + 0.002z⁻¹ + 0.0008z⁻²)/0.0036: steps of 2/9, 5/9, 2/9, then exactly 1.
  std::vector<double> u(64, 0.0);
  for (std::size_t k = 0; k < u.size(); ++k)
    for (std::size_t j = 0; j < f.size() && j <= k; ++j) u[k] += f[j];
  const std::vector<double> y = second_order(64, u);
  CHECK(y[0] == 0.0);
  CHECK(y[1] == Approx(2.0 / 9.0).margin(1e-12));
  CHECK(y[2] == Approx(7.0 / 9.0).margin(1e-12));
  for (int k = 3; k < 64; ++k) CHECK(y[static_cast<std::size_t>(k)] == Approx(1.0).margin(1e-12));
  // Without F it creeps up: 10⁻³ from 1 still at k = 30.
  CHECK(1.0 - second_order(31)[30] > 1e-3);
}

TEST_CASE("identify_loop: a loop of order past 12 is not identified") {
  // A pure delay of 20 samples (y_k = u_{k−20}) needs deg B = 20.
  std::vector<double> s(4096, 0.0);
  for (std::size_t k = 20; k < s.size(); ++k) s[k] = 1.0;
  CHECK(gm::identify_loop(s).a.empty());
  CHECK(gm::zpetc_weights(gm::LoopModel{{1.0}, {0.0}}).empty());  // B(1) = 0
}
