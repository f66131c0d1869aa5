// Tap design against closed forms computed here: linear, S-curves (Eq. 23), fir1 windows, custom.
#include "accdec/taps.hpp"
#include "common/status.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <numeric>
#include <string>
#include <vector>

using gm::design_taps;
using gm::Taps;

namespace {

constexpr double kPi = 3.14159265358979323846;

double sinc(double x) {
  return x == 0 ? 1.0 : std::sin(kPi * x) / (kPi * x);
}

// Matlab fir1(N, wc, win) low-pass computed independently: wc·sinc(wc(n - N/2))·win[n], sum 1.
std::vector<double> ref_fir1(int N, double wc, const std::vector<double>& win) {
  std::vector<double> h;
  for (int n = 0; n <= N; ++n)
    h.push_back(wc * sinc(wc * (n - N / 2.0)) * win[static_cast<std::size_t>(n)]);
  const double s = std::accumulate(h.begin(), h.end(), 0.0);
  for (double& v : h) v /= s;
  return h;
}

std::vector<double> ref_window(const std::string& kind, int M, double beta = 0) {
  std::vector<double> w;
  for (int n = 0; n < M; ++n) {
    const double x = static_cast<double>(n) / (M - 1);
    if (kind == "blackman")
      w.push_back(0.42 - 0.5 * std::cos(2 * kPi * x) + 0.08 * std::cos(4 * kPi * x));
    if (kind == "hann") w.push_back(0.5 * (1 - std::cos(2 * kPi * x)));
    if (kind == "hamming") w.push_back(0.54 - 0.46 * std::cos(2 * kPi * x));
    if (kind == "kaiser") {
      const double r = 2 * x - 1;
      w.push_back(std::cyl_bessel_i(0.0, beta * std::sqrt(1 - r * r)) /
                  std::cyl_bessel_i(0.0, beta));
    }
  }
  return w;
}

void check_integer_consistent(const Taps& t) {
  REQUIRE(t.integer.size() == t.real.size());
  std::int64_t sum = 0;
  for (auto b : t.integer) {
    CHECK(b >= 0);
    sum += b;
  }
  CHECK(sum == t.b_s);
  for (std::size_t i = 0; i < t.real.size(); ++i)
    if (t.real[i] > 0) CHECK(t.integer[i] >= 1);
}

}  // namespace

TEST_CASE("linear taps: N+1 = tau/T equal taps, integer taps 1, b_s = N+1 (Eq. 15)") {
  const Taps t = design_taps("linear", 0.164, 0.004);
  CHECK(t.N == 40);
  REQUIRE(t.real.size() == 41);
  for (double b : t.real) CHECK(b == Approx(1.0 / 41).epsilon(1e-14));
  for (auto b : t.integer) CHECK(b == 1);
  CHECK(t.b_s == 41);
  CHECK(std::isnan(t.cutoff));
  CHECK(t.integer_exact);
}

TEST_CASE("S-curve taps follow Eq. 22a/22b and Eq. 23 (n = 41)") {
  const int n = 41;
  for (int degree : {1, 2}) {
    INFO("S-curve " << degree);
    std::vector<double> a;
    for (int k = 1; k <= n; ++k) {
      const double t = static_cast<double>(k) / n;
      a.push_back(degree == 1 ? 6 * t - 6 * t * t
                              : 30 * t * t - 60 * t * t * t + 30 * t * t * t * t);
    }
    const double s = std::accumulate(a.begin(), a.end(), 0.0);
    const Taps t = design_taps(degree == 1 ? "scurve1" : "scurve2", 0.164, 0.004);
    REQUIRE(t.real.size() == static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      CHECK(t.real[static_cast<std::size_t>(i)] ==
            Approx(a[static_cast<std::size_t>(i)] / s).margin(1e-15));
      // Integer taps exactly proportional (a' ∝ k(n-k) or k²(n-k)², integers).
      CHECK(static_cast<double>(t.integer[static_cast<std::size_t>(i)]) /
                static_cast<double>(t.b_s) ==
            Approx(a[static_cast<std::size_t>(i)] / s).margin(1e-15));
    }
    CHECK(t.real.back() == 0.0);  // a'(1) = 0: Eq. 23 keeps a zero last tap
    CHECK(t.integer_exact);
    check_integer_consistent(t);
  }
  // Hand-worked: n = 4, S-curve 1: k(n-k) = 3, 4, 3, 0 -> b_s = 10.
  const Taps small = design_taps("scurve1", 0.016, 0.004);
  CHECK(small.integer == std::vector<std::int64_t>{3, 4, 3, 0});
  CHECK(small.b_s == 10);
}

TEST_CASE(
    "section 6 Blackman design: N = 40, cutoff 2/41, taps = fir1 with Blackman window, all >= 0") {
  const Taps t = design_taps("blackman", 0.164, 0.004);
  CHECK(t.N == 40);
  CHECK(t.cutoff == Approx(2.0 / 41).epsilon(1e-15));
  CHECK(t.cutoff == Approx(0.049).margin(5e-4));
  const auto ref = ref_fir1(40, 2.0 / 41, ref_window("blackman", 41));
  REQUIRE(t.real.size() == ref.size());
  double sum = 0;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    CHECK(t.real[i] == Approx(ref[i]).margin(1e-15));
    CHECK(t.real[i] >= 0.0);
    sum += t.real[i];
  }
  CHECK(sum == Approx(1.0).epsilon(1e-14));
  CHECK(t.real.front() == 0.0);  // the window is zero at both ends
  CHECK(t.real.back() == 0.0);
  check_integer_consistent(t);
  const auto peak = *std::max_element(t.integer.begin(), t.integer.end());
  CHECK(peak == 65536);
  CHECK(t.b_s == std::accumulate(t.integer.begin(), t.integer.end(), std::int64_t{0}));
}

TEST_CASE("the largest non-negative Blackman cutoff is 2/(N-2), not 2/(N+1), Hamming's is 2/N") {
  for (int N : {10, 40, 41}) {
    INFO("N = " << N);
    const auto w = ref_window("blackman", N + 1);
    auto min_interior = [&](double wc) {
      const auto h = ref_fir1(N, wc, w);
      return *std::min_element(h.begin() + 1, h.end() - 1);
    };
    const double wmax = 2.0 / (N - 2);
    CHECK(min_interior(2.0 / (N + 1)) > 0.0);
    CHECK(min_interior(wmax * (1 - 1e-9)) >= 0.0);
    CHECK(min_interior(wmax * (1 + 1e-4)) < 0.0);
    const double tau = (N + 1) * 0.004;
    CHECK(design_taps("blackman", tau, 0.004).max_nonneg_cutoff == Approx(wmax).epsilon(1e-15));
    const Taps at_max = design_taps("blackman@max", tau, 0.004);
    CHECK(at_max.cutoff == Approx(wmax).epsilon(1e-15));
    for (double b : at_max.real) CHECK(b >= 0.0);
    CHECK_THROWS_AS(design_taps("blackman@" + std::to_string(wmax * 1.01), tau, 0.004),
                    gm::InputError);
  }
  const auto wh = ref_window("hamming", 41);
  const auto h = ref_fir1(40, 2.0 / 40 * (1 + 1e-4), wh);
  CHECK(std::min(h.front(), h.back()) < 0.0);
  CHECK(design_taps("hamming", 0.164, 0.004).max_nonneg_cutoff == Approx(2.0 / 40).epsilon(1e-15));
}

TEST_CASE("hann, hamming and kaiser window designs match fir1 computed here") {
  struct Case {
    std::string spec, window;
    double beta;
  };
  for (const Case& c : {Case{"hann", "hann", 0}, Case{"hamming", "hamming", 0},
                        Case{"kaiser:6", "kaiser", 6}, Case{"kaiser:2.5", "kaiser", 2.5}}) {
    INFO(c.spec);
    const Taps t = design_taps(c.spec, 0.084, 0.004);  // 21 taps
    CHECK(t.N == 20);
    const auto ref = ref_fir1(20, 2.0 / 21, ref_window(c.window, 21, c.beta));
    for (std::size_t i = 0; i < ref.size(); ++i) CHECK(t.real[i] == Approx(ref[i]).margin(1e-14));
    check_integer_consistent(t);
  }
}

TEST_CASE("custom and cascade taps") {
  const Taps t = design_taps("custom:0.5,1,2,1,0.5", 0.02, 0.004);
  CHECK(t.N == 4);
  CHECK(t.integer == std::vector<std::int64_t>{1, 2, 4, 2, 1});
  CHECK(t.b_s == 10);
  CHECK(t.real[2] == Approx(0.4).epsilon(1e-15));
  const Taps c = design_taps("cascade:3,2", 0.016, 0.004);
  CHECK(c.integer == std::vector<std::int64_t>{1, 2, 2, 1});  // [1,1,1]*[1,1]
  const Taps c3 = design_taps("cascade:3,3", 0.020, 0.004);
  CHECK(c3.integer == std::vector<std::int64_t>{1, 2, 3, 2, 1});
}

TEST_CASE("bad specs and taus are rejected with messages naming the value") {
  auto message = [](auto&& f) -> std::string {
    try {
      f();
    } catch (const gm::InputError& e) {
      return e.what();
    }
    return "(no exception)";
  };
  const auto neg = message([] { design_taps("custom:1,2,-0.5,1", 0.016, 0.004); });
  CHECK(neg.find("b2") != std::string::npos);
  CHECK(neg.find("negative") != std::string::npos);
  const auto tau = message([] { design_taps("linear", 0.041, 0.004); });
  CHECK(tau.find("0.041") != std::string::npos);
  CHECK(tau.find("0.004") != std::string::npos);
  CHECK(tau.find("10.25") != std::string::npos);
  CHECK(message([] { design_taps("trapezoid", 0.164, 0.004); }).find("trapezoid") !=
        std::string::npos);
  CHECK(message([] { design_taps("custom:1,2,1", 0.164, 0.004); }).find("3 taps") !=
        std::string::npos);
  CHECK(message([] { design_taps("kaiser:x", 0.164, 0.004); }).find("'x'") != std::string::npos);
  CHECK(message([] { design_taps("cascade:2,0", 0.004, 0.004); }).find("L2") != std::string::npos);
  CHECK_THROWS_AS(design_taps("linear", 0.0, 0.004), gm::InputError);
  CHECK_THROWS_AS(design_taps("linear", 0.001, 0.004), gm::InputError);
  CHECK_THROWS_AS(design_taps("blackman@1.5", 0.164, 0.004), gm::InputError);
  CHECK_NOTHROW(design_taps("linear", 0.004, 0.004));
  // Blackman and Hann windows of 2 points are all zero.
  CHECK(message([] { design_taps("blackman", 0.008, 0.004); }).find("all-zero") !=
        std::string::npos);
  CHECK_NOTHROW(design_taps("blackman", 0.012, 0.004));
}

TEST_CASE("Step 3 scaling: largest tap 2^16, positive taps never round to zero") {
  bool exact = true;
  const auto ints = gm::integerize_taps({1e-9, 0.3, 0.7 / 3.0, 0.5}, exact);
  CHECK_FALSE(exact);
  CHECK(ints[0] == 1);
  CHECK(ints[3] == 65536);
  CHECK(ints[1] == std::llround(0.3 / 0.5 * 65536));
}
