// Acc/Dec tap design (paper sections 2, 4, 5): profile spec + tau + T -> real and integer taps.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace gm {

/// Most Acc/Dec taps tau/T a filter may have (tau = 100 s at T = 1 ms): beyond it the design and
/// the filter's history grow without bound, so machine files and flags asking for more are refused.
inline constexpr int kMaxAccDecTaps = 100000;

/// A designed Acc/Dec filter D(z) = (1/b_s) Σ b_i z^-i, i = 0..N (Eq. 8). Designing is separate
/// from applying (FirAccDec applies `integer`).
struct Taps {
  std::string profile;                ///< the spec it came from
  int N = 0;                          ///< filter order; N+1 taps; tau = (N+1)T (Eq. 24)
  double cutoff = 0;                  ///< normalised to Nyquist for window designs, else NaN
  std::vector<double> real;           ///< the designed taps, DC gain 1 (sum = 1)
  std::vector<std::int64_t> integer;  ///< integer taps (Step 3), all >= 0, applied by FirAccDec
  std::int64_t b_s = 0;               ///< position convergent factor: sum of integer taps (Eq. 5)
  bool integer_exact = false;         ///< integer taps are exactly proportional to `real`
  double max_nonneg_cutoff = 0;  ///< window designs: largest cutoff with all taps >= 0, else NaN
};

/// Designs the taps of `profile_spec` (see profile_spec.hpp) for time constant `tau_s` and
/// sampling period `period_s` (both seconds): N + 1 = tau/T taps.
/// Throws gm::InputError when tau/T is not within 1e-6 of an integer >= 1, when a fixed-length
/// profile (custom, cascade) does not have tau/T taps, when a tap is negative (naming it), or
/// when the spec is malformed.
Taps design_taps(std::string_view profile_spec, double tau_s, double period_s);

/// Number of taps tau/T for a time constant and period, or throws gm::InputError naming both
/// values when the ratio is not within 1e-6 (relative) of an integer >= 1.
int tap_count(double tau_s, double period_s);

/// Step 3: integer taps for real taps (all >= 0, sum > 0). If the taps are exactly proportional
/// to small integers (every tap times some m in 1..1000 is within 1e-9 of an integer, and the
/// largest integer is <= 2^24), those integers divided by their gcd are used (exact shape).
/// Otherwise the taps are scaled so the largest is 2^16 and rounded to nearest; a positive
/// real tap never rounds to 0 (it becomes 1). Sets `exact` accordingly.
std::vector<std::int64_t> integerize_taps(const std::vector<double>& real, bool& exact);

/// The weights' support [first, end): their leading and trailing zero weights left out (the
/// S-curves end in one, Blackman and Hann windows in one at each end, an overshooting chain is
/// lengthened by zeros). A window is symmetric when its support is.
inline std::pair<std::size_t, std::size_t> weights_support(const std::vector<double>& h) {
  std::size_t first = 0, end = h.size();
  while (first < end && h[first] == 0.0) ++first;
  while (end > first && h[end - 1] == 0.0) --end;
  return {first, end};
}

/// Whether the weights' support is symmetric (mirrored weights within 1e-12).
inline bool weights_symmetric(const std::vector<double>& h) {
  const auto [first, end] = weights_support(h);
  for (std::size_t i = first, j = end; i < j; ++i)
    if (std::abs(h[i] - h[--j]) > 1e-12) return false;
  return true;
}

/// The gain of the weights at x rad/sample about `centre` (Σ i·h_i): for symmetric ones the real
/// A(x) = Σ h_i cos((i − centre)·x), sign and all; otherwise |Σ h_i e^{−j·i·x}|.
inline double weights_gain(const std::vector<double>& h, double centre, bool symmetric, double x) {
  double a = 0.0, b = 0.0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    a += h[i] * std::cos((static_cast<double>(i) - centre) * x);
    if (!symmetric) b += h[i] * std::sin((static_cast<double>(i) - centre) * x);
  }
  return symmetric ? a : std::hypot(a, b);
}

}  // namespace gm
