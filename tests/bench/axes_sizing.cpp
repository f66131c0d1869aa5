// Per-sample cost of the axis vectors' sizing: compile-time N vs nine with an active-axis list.
// Models one sample of the hot path per axis: interpolated position -> BLU rounding, a 41-tap
// FIR dot product over a window, and a second-order servo update with a quantised encoder.
// Built by the bench preset (build-bench/bin/gmotion_axes_sizing), or alone: g++ -std=c++20 -O3
//   -I/usr/include/eigen3 tests/bench/axes_sizing.cpp -o axes_sizing (figures: docs/performance.md)
#include <Eigen/Core>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

constexpr int kTaps = 41;

template <int N>
struct State {
  Eigen::Matrix<double, N, 1> pos_mm = Eigen::Matrix<double, N, 1>::Zero();
  Eigen::Matrix<double, N, 1> blu_mm = Eigen::Matrix<double, N, 1>::Constant(0.001);
  std::array<std::array<double, kTaps * 2>, N> window{};  // mirrored ring per axis
  std::array<double, kTaps> taps{};
  Eigen::Matrix<double, N, 1> x1 = Eigen::Matrix<double, N, 1>::Zero(), x2 = x1, integ = x1;
  Eigen::Matrix<std::int64_t, N, 1> enc = Eigen::Matrix<std::int64_t, N, 1>::Zero();
  int head = 0;
};

// Work on axes `idx[0..count)` (count == N for compile-time sizes).
template <int N, bool UseList>
double run(int samples, int count, const std::array<int, 9>& idx) {
  State<N> s;
  for (int i = 0; i < kTaps; ++i) s.taps[i] = 1.0 / kTaps;
  double sink = 0;
  for (int k = 0; k < samples; ++k) {
    const double th = 1e-4 * k;
    const double c = std::cos(th), sn = std::sin(th);
    const int n = UseList ? count : N;
    for (int j = 0; j < n; ++j) {
      const int a = UseList ? idx[j] : j;
      s.pos_mm[a] = (a % 3 == 0 ? c : a % 3 == 1 ? sn : 1e-3 * k) * (1 + a);
      const std::int64_t cmd = std::llround(s.pos_mm[a] / s.blu_mm[a]);
      auto& w = s.window[a];
      w[s.head] = w[s.head + kTaps] = static_cast<double>(cmd);
      double acc = 0;
      for (int i = 0; i < kTaps; ++i) acc += s.taps[i] * w[s.head + 1 + i];
      const std::int64_t ref = std::llround(acc);
      // servo: PI velocity loop on a second-order plant, quantised encoder
      const double err = static_cast<double>(ref - s.enc[a]);
      s.integ[a] += 0.01 * err;
      const double u = 3.0 * err + s.integ[a] - 0.5 * s.x2[a];
      s.x2[a] = 0.9 * s.x2[a] + 0.1 * u;
      s.x1[a] += 0.004 * s.x2[a];
      s.enc[a] = std::llround(s.x1[a]);
      sink += static_cast<double>(s.enc[a]);
    }
    s.head = (s.head + kTaps - 1) % kTaps;
  }
  return sink;
}

template <int N, bool UseList>
void measure(const char* name, int count, const std::array<int, 9>& idx) {
  const int samples = 2'000'000;
  double best = 1e30, sink = 0;
  for (int r = 0; r < 7; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    sink += run<N, UseList>(samples, count, idx);
    const double ns =
        std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() /
        samples;
    best = std::min(best, ns);
  }
  std::printf("%-34s %6.1f ns/sample  (%d active axes)   [%g]\n", name, best, count,
              sink > 0 ? 0.0 : 1.0);
}

int main() {
  const std::array<int, 9> xyz{0, 1, 2}, xyza{0, 1, 2, 3}, six{0, 1, 2, 3, 4, 5},
      nine{0, 1, 2, 3, 4, 5, 6, 7, 8};
  for (int rep = 0; rep < 2; ++rep) {
    measure<3, false>("compile-time 3", 3, xyz);
    measure<9, true>("nine wide, list of 3 active", 3, xyz);
    measure<9, false>("nine wide, all nine computed", 9, nine);
    measure<4, false>("compile-time 4", 4, xyza);
    measure<9, true>("nine wide, list of 4 active", 4, xyza);
    measure<6, false>("compile-time 6", 6, six);
    measure<9, true>("nine wide, list of 6 active", 6, six);
  }
}
