// Window functions and the fir1 windowed ideal low-pass design (paper section 5, Eq. 24-25).
#include "accdec/window.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gm {

double bessel_i0(double x) {
  // I0(x) = sum_k ((x/2)^k / k!)^2, converges for all x; stop when the term is negligible.
  const double q = x * x / 4.0;
  double term = 1.0;
  double sum = 1.0;
  for (int k = 1; k < 500; ++k) {
    term *= q / (static_cast<double>(k) * static_cast<double>(k));
    sum += term;
    if (term < sum * 1e-17) break;
  }
  return sum;
}

std::vector<double> make_window(WindowKind kind, int points, double kaiser_beta) {
  std::vector<double> w(static_cast<std::size_t>(std::max(points, 0)), 1.0);
  if (points <= 1) return w;
  const double pi = std::numbers::pi;
  const double m = points - 1;
  for (int n = 0; n < points; ++n) {
    const double x = n / m;  // 0..1
    double v = 1.0;
    switch (kind) {
      case WindowKind::Blackman:
        v = 0.42 - 0.5 * std::cos(2 * pi * x) + 0.08 * std::cos(4 * pi * x);
        break;
      case WindowKind::Hann:
        v = 0.5 - 0.5 * std::cos(2 * pi * x);
        break;
      case WindowKind::Hamming:
        v = 0.54 - 0.46 * std::cos(2 * pi * x);
        break;
      case WindowKind::Kaiser: {
        const double r = 2 * x - 1;
        v = bessel_i0(kaiser_beta * std::sqrt(std::max(0.0, 1 - r * r))) / bessel_i0(kaiser_beta);
        break;
      }
    }
    if (std::abs(v) < 1e-15) v = 0.0;
    w[static_cast<std::size_t>(n)] = v;
  }
  return w;
}

std::vector<double> fir1_lowpass(int order_N, double cutoff, const std::vector<double>& window) {
  const double pi = std::numbers::pi;
  std::vector<double> h(static_cast<std::size_t>(order_N + 1));
  for (int n = 0; n <= order_N; ++n) {
    const double x = cutoff * (n - order_N / 2.0);
    const double sinc = x == 0.0 ? 1.0 : std::sin(pi * x) / (pi * x);
    h[static_cast<std::size_t>(n)] = cutoff * sinc * window[static_cast<std::size_t>(n)];
  }
  double peak = 0.0;
  for (double v : h) peak = std::max(peak, std::abs(v));
  double sum = 0.0;
  for (double& v : h) {
    if (std::abs(v) < 1e-12 * peak) v = 0.0;
    sum += v;
  }
  if (sum != 0.0)
    for (double& v : h) v /= sum;
  return h;
}

double max_nonnegative_cutoff(WindowKind kind, int order_N) {
  const bool zero_ends = kind == WindowKind::Blackman || kind == WindowKind::Hann;
  // Outermost sample with a non-zero window sits at offset N/2 (or N/2 - 1 if the ends are zero)
  // from the centre; sinc(c·offset) >= 0 needs c·offset <= 1.
  const double offset = zero_ends ? order_N / 2.0 - 1.0 : order_N / 2.0;
  if (offset <= 1.0) return 1.0;  // too short for a negative lobe: any cutoff in (0,1] works
  return std::min(1.0, 1.0 / offset);
}

}  // namespace gm
