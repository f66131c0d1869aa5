// Corner and arc closed forms against hand-worked values and the real FIR filter.
#include "accdec/analysis.hpp"
#include "accdec/fir_filter.hpp"
#include "accdec/taps.hpp"
#include "planner/filter_moments.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace {

constexpr double kPi = 3.14159265358979323846;

// Distance from p to the segment a-b.
double seg_dist(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  const double u = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p - (a + u * d)).norm();
}

struct CornerSim {
  double max_err_blu = 0;     // largest distance of the output to the two legs
  double max_vertex_blu = 0;  // output distance to the vertex at the crossing sample
};

// Drives the real FirAccDec with an interpolator-like input: `v` BLU per sample along +x for
// `leg` samples, a pause of `pause` samples at the vertex, then `leg` samples along the
// direction turned by `phi`; the vertex is reached exactly on a sample.
CornerSim simulate_corner(const gm::Taps& taps, double v, double phi, int pause, int leg) {
  gm::FirAccDec fir(taps, gm::AxisBlu::Zero());
  const Eigen::Vector2d a(0, 0), c(v * leg, 0);
  const Eigen::Vector2d u2(std::cos(phi), std::sin(phi));
  const Eigen::Vector2d e = c + v * leg * u2;
  CornerSim r;
  const int n = static_cast<int>(taps.integer.size());
  const int total = 2 * leg + pause + 2 * n;
  for (int k = 0; k <= total; ++k) {
    Eigen::Vector2d x;
    if (k <= leg)
      x = a + Eigen::Vector2d(v * k, 0);
    else if (k <= leg + pause)
      x = c;
    else
      x = c + std::min(v * (k - leg - pause), v * leg) * u2;
    gm::AxisBlu in = gm::AxisBlu::Zero(), out;
    in[0] = std::llround(x[0]);
    in[1] = std::llround(x[1]);
    fir.step(in, out);
    const Eigen::Vector2d y(static_cast<double>(out[0]), static_cast<double>(out[1]));
    const double d = std::min(seg_dist(y, a, c), seg_dist(y, c, e));
    r.max_err_blu = std::max(r.max_err_blu, d);
    // The crossing instant t = mT + P/2 after the vertex (a sample when m and P/2 are whole).
    if (2 * k == 2 * leg + (n - 1) + pause) r.max_vertex_blu = (y - c).norm();
  }
  return r;
}

}  // namespace

TEST_CASE("corner moment D: hand-worked moving average and the closed form for any pause") {
  // 25 equal taps, T = 4 ms: m = 12, D = T·Σ_{i<12} (12 − i)/25 = T·78/25 = 12.48 ms.
  const gm::Taps lin = gm::design_taps("linear", 0.1, 0.004);
  const gm::FilterMoments f(lin, 0.004);
  CHECK(f.centre() == Approx(12.0).epsilon(1e-14));
  CHECK(f.corner_moment_closed_s(0.0) == Approx(0.004 * 78.0 / 25.0).epsilon(1e-13));
  CHECK(f.corner_moment_s(0.0) == Approx(0.004 * 78.0 / 25.0).epsilon(1e-9));
  // Pause 2T: T·Σ h_i max(i − 13, 0) = T·(1 + … + 11)/25 = T·66/25.
  CHECK(f.corner_moment_s(0.008) == Approx(0.004 * 66.0 / 25.0).epsilon(1e-9));
  // σ² = T²·(n² − 1)/12 for n equal taps.
  CHECK(f.variance_s2() == Approx(0.004 * 0.004 * (625.0 - 1.0) / 12.0).epsilon(1e-12));
  for (const char* prof : {"linear", "blackman", "hann", "scurve1"}) {
    const gm::Taps t = gm::design_taps(prof, 0.164, 0.004);
    const gm::FilterMoments g(t, 0.004);
    double last = 1.0;
    for (double p = 0.0; p <= 0.17; p += 0.0013) {
      const double d = g.corner_moment_s(p);
      CHECK(d == Approx(g.corner_moment_closed_s(p)).margin(1e-12));
      CHECK(d <= last + 1e-15);  // pausing never makes it worse
      last = d;
    }
    CHECK(g.corner_moment_s(g.order() * 0.004) == Approx(0.0).margin(1e-15));
  }
}

TEST_CASE("corner error F·D(P)·sin φ and vertex distance 2·F·D(P)·sin(φ/2) match the real FIR") {
  // v = 4000 BLU per sample (1 m/s at 1 µm BLU and T = 4 ms): the output's integer rounding is
  // a few 1e-5 of the errors. The crossing instant mT + P/2 falls on a sample for even P.
  for (const char* prof : {"linear", "blackman"}) {
    const double tau = std::string(prof) == "linear" ? 0.1 : 0.164;
    const gm::Taps t = gm::design_taps(prof, tau, 0.004);
    const gm::FilterMoments f(t, 0.004);
    const double v = 4000.0, speed = v / 0.004;  // BLU per sample, BLU per second
    for (double deg : {20.0, 45.0, 90.0, 135.0}) {
      const double phi = deg * kPi / 180.0;
      for (int pause : {0, 2, 6, 10, 20}) {
        CAPTURE(prof, deg, pause);
        const CornerSim s = simulate_corner(t, v, phi, pause, 200);
        const double closed = f.corner_error_mm(speed, phi, pause * 0.004);
        const double vertex = f.vertex_error_mm(speed, phi, pause * 0.004);
        CHECK(s.max_err_blu == Approx(closed).margin(2.0));
        CHECK(s.max_vertex_blu == Approx(vertex).margin(2.0));
      }
      // Odd pauses: the crossing falls between samples; the sampled error is at most the form.
      for (int pause : {1, 3, 7}) {
        const CornerSim s = simulate_corner(t, v, phi, pause, 200);
        CHECK(s.max_err_blu <= f.corner_error_mm(speed, phi, pause * 0.004) + 1.0);
        CHECK(s.max_err_blu >= f.corner_error_mm(speed, phi, (pause + 1) * 0.004) - 1.0);
      }
    }
  }
  // The figure: a 20 mm square at F6000 (100 mm/s) on the default machine.
  const gm::FilterMoments bk(gm::design_taps("blackman", 0.164, 0.004), 0.004);
  CHECK(bk.corner_error_mm(100.0, kPi / 2, 0.0) == Approx(0.894).margin(0.001));
}

TEST_CASE("largest corner speed and shortest pause invert the corner error") {
  const gm::FilterMoments f(gm::design_taps("blackman", 0.164, 0.004), 0.004);
  const double v = f.largest_corner_speed_mm_s(0.01, kPi / 2, 0.0);
  CHECK(f.corner_error_mm(v, kPi / 2, 0.0) == Approx(0.01).epsilon(1e-12));
  const double p = f.shortest_pause_s(0.01, kPi / 2, 100.0);
  CHECK(f.corner_error_mm(100.0, kPi / 2, p) <= 0.01 + 1e-12);
  CHECK(f.corner_error_mm(100.0, kPi / 2, p - 1e-4) > 0.01);
  CHECK(p < f.order() * 0.004);
}

TEST_CASE("arc: steady radius loss of the real FIR equals Eq. 13/14 and stays below κV²σ²/2") {
  for (const char* prof : {"linear", "blackman"}) {
    const gm::Taps t = gm::design_taps(prof, 0.164, 0.004);
    const gm::FilterMoments f(t, 0.004);
    for (double wT : {0.01, 0.03, 0.08}) {
      const double R = 2.0e6;  // BLU
      gm::FirAccDec fir(t, gm::AxisBlu::Zero());
      gm::AxisBlu in = gm::AxisBlu::Zero(), out;
      double worst = 0;
      const int n = static_cast<int>(t.integer.size());
      const int turns_samples = static_cast<int>(4 * kPi / wT) + 3 * n;
      for (int k = 0; k < turns_samples; ++k) {
        in[0] = std::llround(R * std::cos(wT * k) - R);
        in[1] = std::llround(R * std::sin(wT * k));
        fir.step(in, out);
        if (k > 2 * n)
          worst = std::max(
              worst, R - std::hypot(static_cast<double>(out[0]) + R, static_cast<double>(out[1])));
      }
      CAPTURE(prof, wT);
      const double v = R * wT / 0.004;  // BLU per second
      const double eq = gm::radius_loss_sampled(gm::as_double(t.integer), R, v, 0.004);
      CHECK(worst == Approx(eq).margin(1.0));
      const double bound = v * v * f.variance_s2() / (2.0 * R);
      CHECK(eq <= bound);
      if (wT * n < 1.0) CHECK(eq >= 0.9 * bound);  // tight for ωτ small
    }
  }
}

TEST_CASE("signed weights: variance and absolute moment of Σ_j |c_j|·|i − j| (hand-worked, long)") {
  // {0.5, 0.7, −0.2} at T = 1 s: Σ_j |c_j|·|i − j| = 1.1, 0.7, 1.7 for i = 0, 1, 2 (the two zero
  // weights the 0.2 s overshoot appends add nothing), so the variance is
  // 0.5·1.21 + 0.7·0.49 + 0.2·2.89 = 1.526 s² and the absolute moment 0.55 + 0.49 + 0.34 = 1.38 s.
  const gm::FilterMoments small({0.5, 0.7, -0.2}, 1.0);
  CHECK(small.variance_s2() == Approx(1.526).epsilon(1e-12));
  CHECK(small.abs_moment_s() == Approx(1.38).epsilon(1e-12));

  // A long ringing chain (5,000 weights: a decaying oscillation, first weight set for Σ = 1)
  // against the double sum written out.
  const int n = 5000;
  std::vector<double> w(n);
  double rest = 1.0;
  for (int k = 1; k < n; ++k) {
    w[k] = 0.01 * std::exp(-k / 800.0) * std::cos(k * 0.05);
    rest -= w[k];
  }
  w[0] = rest;
  const gm::FilterMoments long_chain(w, 0.001);
  const std::vector<double>& h = long_chain.weights();
  double variance = 0.0, abs_moment = 0.0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    double d = 0.0;
    for (std::size_t j = 0; j < h.size(); ++j)
      d += std::abs(h[j]) * std::abs(static_cast<double>(i) - static_cast<double>(j));
    d *= 0.001;
    variance += std::abs(h[i]) * d * d;
    abs_moment += std::abs(h[i]) * d;
  }
  CHECK(long_chain.variance_s2() == Approx(variance).epsilon(1e-10));
  CHECK(long_chain.abs_moment_s() == Approx(abs_moment).epsilon(1e-10));
}
