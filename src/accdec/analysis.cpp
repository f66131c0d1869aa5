// Amplitude response, radius loss (sampled, Eq. 18, Eq. 19), Eq. 7 and quantisation error.
#include "accdec/analysis.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

namespace gm {

double amplitude_response(const std::vector<double>& taps, double omega_T) {
  std::complex<double> s{0.0, 0.0};
  double sum = 0.0;
  for (std::size_t i = 0; i < taps.size(); ++i) {
    s += taps[i] * std::polar(1.0, -static_cast<double>(i) * omega_T);
    sum += taps[i];
  }
  return std::abs(s) / sum;
}

double radius_loss_sampled(const std::vector<double>& taps, double radius, double v_tan,
                           double period_s) {
  const double theta = v_tan / radius * period_s;  // ωT
  double bs = 0.0;
  for (double b : taps) bs += b;
  double one_minus_sq = 0.0;  // 1 - |D|^2 without cancellation
  for (std::size_t i = 0; i < taps.size(); ++i) {
    if (taps[i] == 0.0) continue;
    for (std::size_t k = i + 1; k < taps.size(); ++k) {
      const double s = std::sin(static_cast<double>(k - i) * theta / 2.0);
      one_minus_sq += taps[i] * taps[k] * 2.0 * s * s;
    }
  }
  one_minus_sq *= 2.0 / (bs * bs);
  const double a = std::sqrt(std::max(0.0, 1.0 - one_minus_sq));
  return radius * one_minus_sq / (1.0 + a);
}

double radius_loss_linear_continuous(double radius, double v_tan, double tau_s) {
  const double u = tau_s * (v_tan / radius) / 2.0;
  double one_minus_sinc;
  if (std::abs(u) < 0.1) {  // series through u^8; the next term is < 2e-15 relative
    const double u2 = u * u;
    one_minus_sinc = u2 / 6.0 * (1.0 - u2 / 20.0 * (1.0 - u2 / 42.0 * (1.0 - u2 / 72.0)));
  } else {
    one_minus_sinc = 1.0 - std::sin(u) / u;
  }
  return radius * one_minus_sinc;
}

double radius_loss_linear_approx(double radius, double v_tan, double tau_s) {
  const double tv = tau_s * v_tan;
  return tv * tv / (24.0 * radius);
}

double peak_acceleration(const std::vector<double>& taps, double v_step, double period_s) {
  double bs = 0.0;
  double peak = 0.0;
  for (double b : taps) {
    bs += b;
    peak = std::max(peak, b);
  }
  return v_step * peak / (period_s * bs);
}

std::vector<double> as_double(const std::vector<std::int64_t>& taps) {
  std::vector<double> d(taps.size());
  std::transform(taps.begin(), taps.end(), d.begin(),
                 [](std::int64_t b) { return static_cast<double>(b); });
  return d;
}

double quantisation_error(const Taps& taps, int points) {
  const auto ints = as_double(taps.integer);
  double worst = 0.0;
  for (int j = 0; j < points; ++j) {
    const double w = std::numbers::pi * j / std::max(1, points - 1);
    worst =
        std::max(worst, std::abs(amplitude_response(ints, w) - amplitude_response(taps.real, w)));
  }
  return worst;
}

}  // namespace gm
