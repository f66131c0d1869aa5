// Tap design (Eq. 24, Step 3): tau/T taps from the profile's registry row, normalised and made
// integer.
#include "accdec/taps.hpp"

#include "accdec/profile_spec.hpp"
#include "accdec/profiles.hpp"
#include "common/status.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace gm {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::vector<double> normalised(std::vector<double> b) {
  double sum = 0;
  for (double v : b) sum += v;
  for (double& v : b) v /= sum;
  return b;
}

}  // namespace

int tap_count(double tau_s, double period_s) {
  if (!(period_s > 0) || !std::isfinite(period_s))
    throw InputError(fmt::format("sampling period T = {} s must be > 0", period_s));
  if (!(tau_s > 0) || !std::isfinite(tau_s))
    throw InputError(fmt::format("Acc/Dec time constant tau = {} s must be > 0", tau_s));
  const double ratio = tau_s / period_s;
  const double n = std::round(ratio);
  if (ratio > kMaxAccDecTaps + 0.5)
    throw InputError(
        fmt::format("Acc/Dec time constant tau = {} s is {:.6g} periods T = {} s; at most {} taps "
                    "(tau <= {:.6g} s)",
                    tau_s, ratio, period_s, kMaxAccDecTaps, kMaxAccDecTaps * period_s));
  if (n < 1 || std::abs(ratio - n) > 1e-6 * std::max(1.0, n))
    throw InputError(
        fmt::format("Acc/Dec time constant tau = {} s is not a whole number of periods T = {} s "
                    "(tau/T = {:.6g}); Eq. 24 needs tau = (N+1)T with N+1 an integer >= 1",
                    tau_s, period_s, ratio));
  return static_cast<int>(n);
}

std::vector<std::int64_t> integerize_taps(const std::vector<double>& real, bool& exact) {
  double peak = 0;
  for (double v : real) peak = std::max(peak, v);
  std::vector<std::int64_t> out(real.size(), 0);
  // Exact: a small multiplier making every tap an integer.
  for (int m = 1; m <= 1000 && peak > 0; ++m) {
    bool ok = true;
    for (double v : real) {
      const double s = v * m;
      if (std::abs(s - std::round(s)) > 1e-9 * std::max(1.0, std::abs(s)) || s > 16777216.0 ||
          (v > 0 && std::round(s) < 1)) {
        ok = false;
        break;
      }
    }
    if (!ok) continue;
    std::int64_t g = 0;
    for (std::size_t i = 0; i < real.size(); ++i) {
      out[i] = static_cast<std::int64_t>(std::llround(real[i] * m));
      g = std::gcd(g, out[i]);
    }
    if (g > 1)
      for (auto& v : out) v /= g;
    exact = true;
    return out;
  }
  exact = false;
  const double scale = 65536.0 / peak;
  for (std::size_t i = 0; i < real.size(); ++i) {
    out[i] = static_cast<std::int64_t>(std::llround(real[i] * scale));
    if (real[i] > 0 && out[i] == 0) out[i] = 1;
  }
  return out;
}

Taps design_taps(std::string_view profile_spec, double tau_s, double period_s) {
  const ProfileSpec spec = parse_profile_spec(profile_spec);
  const int n = tap_count(tau_s, period_s);
  Taps t;
  t.profile = spec.text;
  t.N = n - 1;
  t.cutoff = kNaN;
  t.max_nonneg_cutoff = kNaN;
  if (const int fixed = spec.fixed_length(period_s); fixed > 0 && fixed != n)
    throw InputError(
        fmt::format("profile '{}' has {} taps, so tau must be {} x T = {:.6g} s; got tau = {} s "
                    "(tau/T = {})",
                    spec.text, fixed, fixed, fixed * period_s, tau_s, n));

  const std::vector<double> raw = spec.row->design(spec, TapRequest{n, tau_s, period_s}, t);
  for (std::size_t i = 0; i < raw.size(); ++i)
    if (raw[i] < 0)
      throw InputError(fmt::format(
          "profile '{}' (N = {}, cutoff {:.6g}) gives tap b{} = {:.6g} < 0; section 2 requires "
          "every b_i >= 0 (largest non-negative cutoff here: {:.6g})",
          spec.text, t.N, t.cutoff, i, raw[i], t.max_nonneg_cutoff));
  t.real = normalised(raw);
  // The raw taps are proportional to `real`; integers there (linear, S-curves, cascades,
  // simple custom taps) are kept exactly.
  t.integer = integerize_taps(raw, t.integer_exact);
  t.b_s = std::accumulate(t.integer.begin(), t.integer.end(), std::int64_t{0});
  return t;
}

}  // namespace gm
