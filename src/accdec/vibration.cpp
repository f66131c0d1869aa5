// Residual vibration ratio of impulses or taps for a damped mode, and the band where it is small.
#include "accdec/vibration.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gm {

namespace {

template <typename TimeOf>
double residual(const std::vector<double>& amp, TimeOf time_of, double freq_hz, double z) {
  std::size_t last = amp.size();
  double sum = 0.0;
  for (std::size_t i = 0; i < amp.size(); ++i) {
    sum += amp[i];
    if (amp[i] != 0.0) last = i;
  }
  if (last == amp.size() || !(sum != 0.0)) return 0.0;
  const double w = 2.0 * std::numbers::pi * freq_hz;
  const double wd = w * std::sqrt(1.0 - z * z);
  const double t_n = time_of(last);
  double c = 0.0;
  double s = 0.0;
  for (std::size_t i = 0; i <= last; ++i) {
    if (amp[i] == 0.0) continue;
    const double t = time_of(i);
    const double a = amp[i] * std::exp(-z * w * (t_n - t));
    c += a * std::cos(wd * t);
    s += a * std::sin(wd * t);
  }
  return std::hypot(c, s) / std::abs(sum);
}

}  // namespace

double residual_vibration(const ShaperImpulses& impulses, double freq_hz, double damping) {
  return residual(
      impulses.amplitude, [&](std::size_t i) { return impulses.time_s[i]; }, freq_hz, damping);
}

double residual_vibration(const std::vector<double>& taps, double period_s, double freq_hz,
                          double damping) {
  return residual(
      taps, [&](std::size_t i) { return static_cast<double>(i) * period_s; }, freq_hz, damping);
}

FrequencyBand VibrationRobustness::band_at_f(double freq_hz) const {
  for (const FrequencyBand& b : bands)
    if (b.lo_hz <= freq_hz && freq_hz <= b.hi_hz) return b;
  return {freq_hz, freq_hz};
}

VibrationRobustness vibration_robustness(const std::vector<double>& taps, double period_s,
                                         double freq_hz, double damping, double limit) {
  auto v = [&](double f) { return residual_vibration(taps, period_s, f, damping); };
  VibrationRobustness r;
  r.v_at_f = v(freq_hz);
  r.v_minus_20 = v(0.8 * freq_hz);
  r.v_plus_20 = v(1.2 * freq_hz);
  const double lo_end = 0.5 * freq_hz;
  const double hi_end = std::min(2.0 * freq_hz, 1.0 / period_s);
  const int steps = static_cast<int>(std::ceil((hi_end - lo_end) / (freq_hz / 1000.0)));
  // The crossing between a (inside when `a_in`) and b, to 1e-6 f.
  auto crossing = [&](double a, double b, bool a_in) {
    while (std::abs(b - a) > 1e-6 * freq_hz) {
      const double m = 0.5 * (a + b);
      ((v(m) <= limit) == a_in ? a : b) = m;
    }
    return a_in ? a : b;
  };
  double prev_f = lo_end;
  bool prev_in = v(lo_end) <= limit;
  if (prev_in) r.bands.push_back({lo_end, hi_end});
  for (int k = 1; k <= steps; ++k) {
    const double f = k == steps ? hi_end : lo_end + (hi_end - lo_end) * k / steps;
    const bool in = v(f) <= limit;
    if (in && !prev_in) r.bands.push_back({crossing(prev_f, f, false), hi_end});
    if (!in && prev_in) r.bands.back().hi_hz = crossing(prev_f, f, true);
    prev_f = f;
    prev_in = in;
  }
  return r;
}

}  // namespace gm
