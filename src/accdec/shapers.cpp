// Input shaper impulse sequences (closed forms and Singhose's fits) and their taps at period T.
#include "accdec/shapers.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace gm {

namespace {

constexpr double kShaperPi = std::numbers::pi;

// Polynomial c0 + c1·ζ + c2·ζ² + c3·ζ³.
double poly3(const std::array<double, 4>& c, double z) {
  return c[0] + z * (c[1] + z * (c[2] + z * c[3]));
}

// Singhose's fits of the multi-hump EI shapers for a 5 % tolerance: impulse i at
// time_fit[i](ζ)/f with amplitude amp_fit[i](ζ) (the coefficient tables Klipper ships).
constexpr std::array<std::array<double, 4>, 4> k2HumpTime{{{0.0, 0.0, 0.0, 0.0},
                                                           {0.49890, 0.16270, -0.54262, 6.16180},
                                                           {0.99748, 0.18382, -1.58270, 8.17120},
                                                           {1.49920, -0.09297, -0.28338, 1.85710}}};
constexpr std::array<std::array<double, 4>, 4> k2HumpAmp{{{0.16054, 0.76699, 2.26560, -1.22750},
                                                          {0.33911, 0.45081, -2.58080, 1.73650},
                                                          {0.34089, -0.61533, -0.68765, 0.42261},
                                                          {0.15997, -0.60246, 1.00280, -0.93145}}};
constexpr std::array<std::array<double, 4>, 5> k3HumpTime{{{0.0, 0.0, 0.0, 0.0},
                                                           {0.49974, 0.23834, 0.44559, 12.4720},
                                                           {0.99849, 0.29808, -2.36460, 23.3990},
                                                           {1.49870, 0.10306, -2.01390, 17.0320},
                                                           {1.99960, -0.28231, 0.61536, 5.40450}}};
constexpr std::array<std::array<double, 4>, 5> k3HumpAmp{{{0.11275, 0.76632, 3.29160, -1.44380},
                                                          {0.23698, 0.61164, -2.57850, 4.85220},
                                                          {0.30008, -0.19062, -2.14560, 0.13744},
                                                          {0.23775, -0.73297, 0.46885, -2.08650},
                                                          {0.11244, -0.45439, 0.96382, -1.46000}}};

template <std::size_t M>
ShaperImpulses from_fit(const std::array<std::array<double, 4>, M>& time_fit,
                        const std::array<std::array<double, 4>, M>& amp_fit, double freq_hz,
                        double z) {
  ShaperImpulses s;
  for (std::size_t i = 0; i < M; ++i) {
    s.time_s.push_back(poly3(time_fit[i], z) / freq_hz);
    s.amplitude.push_back(poly3(amp_fit[i], z));
  }
  return s;
}

// Singhose's EI fit (a1, a3 and the middle impulse's time as polynomials in ζ and V_tol).
ShaperImpulses ei(double t_d, double z) {
  const double v = kEiVibrationTolerance;
  const double a1 =
      (0.24968 + 0.24961 * v) + ((0.80008 + 1.23328 * v) + (0.49599 + 3.17316 * v) * z) * z;
  const double a3 =
      (0.25149 + 0.21474 * v) + ((-0.83249 + 1.41498 * v) + (0.85181 - 4.90094 * v) * z) * z;
  const double t2 =
      0.4999 + (((0.46159 + 8.57843 * v) * v) +
                (((4.26169 - 108.644 * v) * v) + ((1.75601 + 336.989 * v) * v) * z) * z) *
                   z;
  return {{a1, 1.0 - a1 - a3, a3}, {0.0, t2 * t_d, t_d}};
}

}  // namespace

ShaperImpulses shaper_impulses(ShaperKind kind, double freq_hz, double damping) {
  const double z = damping;
  const double df = std::sqrt(1.0 - z * z);
  const double t_d = 1.0 / (freq_hz * df);
  const double k = std::exp(-z * kShaperPi / df);
  ShaperImpulses s;
  switch (kind) {
    case ShaperKind::ZV:
      s = {{1.0, k}, {0.0, t_d / 2}};
      break;
    case ShaperKind::ZVD:
      s = {{1.0, 2 * k, k * k}, {0.0, t_d / 2, t_d}};
      break;
    case ShaperKind::ZVDD:
      s = {{1.0, 3 * k, 3 * k * k, k * k * k}, {0.0, t_d / 2, t_d, 1.5 * t_d}};
      break;
    case ShaperKind::MZV: {
      const double k34 = std::exp(-0.75 * z * kShaperPi / df);
      const double a1 = 1.0 - 1.0 / std::numbers::sqrt2;
      s = {{a1, (std::numbers::sqrt2 - 1.0) * k34, a1 * k34 * k34}, {0.0, 0.375 * t_d, 0.75 * t_d}};
      break;
    }
    case ShaperKind::EI:
      s = ei(t_d, z);
      break;
    case ShaperKind::TwoHumpEI:
      s = from_fit(k2HumpTime, k2HumpAmp, freq_hz, z);
      break;
    case ShaperKind::ThreeHumpEI:
      s = from_fit(k3HumpTime, k3HumpAmp, freq_hz, z);
      break;
  }
  double sum = 0.0;
  for (double a : s.amplitude) sum += a;
  for (double& a : s.amplitude) a /= sum;
  return s;
}

namespace {

// Sample index k and fraction p of time t at period T (a fraction within 1e-9 of a whole
// sample counts as on it, so impulses on the grid stay single taps).
void split_time(double t_s, double period_s, long long& k, double& p) {
  const double a = t_s / period_s;
  double whole = std::floor(a);
  p = a - whole;
  if (p > 1.0 - 1e-9) {
    whole += 1.0;
    p = 0.0;
  } else if (p < 1e-9) {
    p = 0.0;
  }
  k = static_cast<long long>(whole);
}

}  // namespace

int shaper_tap_count(const ShaperImpulses& impulses, double period_s, int cap) {
  const double last = impulses.duration_s() / period_s;
  if (!(last < static_cast<double>(cap))) return cap;
  long long k = 0;
  double p = 0.0;
  split_time(impulses.duration_s(), period_s, k, p);
  return static_cast<int>(std::min<long long>(cap, k + (p > 0.0 ? 2 : 1)));
}

std::vector<double> shaper_taps(const ShaperImpulses& impulses, double period_s) {
  std::vector<double> taps(static_cast<std::size_t>(shaper_tap_count(impulses, period_s, 1 << 30)),
                           0.0);
  for (std::size_t i = 0; i < impulses.amplitude.size(); ++i) {
    long long k = 0;
    double p = 0.0;
    split_time(impulses.time_s[i], period_s, k, p);
    const auto idx = static_cast<std::size_t>(k);
    taps[idx] += (1.0 - p) * impulses.amplitude[i];
    if (p > 0.0) taps[idx + 1] += p * impulses.amplitude[i];
  }
  return taps;
}

}  // namespace gm
