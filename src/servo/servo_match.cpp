// Servo matching: an axis's reference shaped so that its servo responds as the reference axis's.
#include "servo/servo_match.hpp"

#include "common/status.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace gm {

namespace {
__extension__ using Acc = __int128;  ///< exact sums of count differences times 2^24
}  // namespace

std::vector<double> MatchTaps::weights() const {
  std::vector<double> w;
  w.reserve(integer.size());
  for (const std::int64_t f : integer)
    w.push_back(static_cast<double>(f) / static_cast<double>(kScale));
  return w;
}

ServoMatch::ServoMatch(const Taps& fir, std::vector<MatchTaps> axes) {
  const std::int64_t b_s = std::accumulate(fir.integer.begin(), fir.integer.end(), std::int64_t{0});
  scale_ = b_s * MatchTaps::kScale;
  for (const MatchTaps& t : axes) {
    if (t.axis < 0 || t.axis >= kMaxAxes || t.integer.empty() ||
        std::accumulate(t.integer.begin(), t.integer.end(), std::int64_t{0}) != MatchTaps::kScale)
      throw InputError(
          fmt::format("servo matching: axis {}: taps must sum to {}", t.axis, MatchTaps::kScale));
    if (!(b_s > 0) || b_s > (std::int64_t{1} << 36))
      throw InputError(fmt::format("servo matching: Acc/Dec b_s = {} out of range", b_s));
    Axis a;
    a.axis = t.axis;
    // c = b ∗ F exactly; each |c_i| below 2^62 (every sum of a window then fits 128 bits).
    std::vector<Acc> c(fir.integer.size() + t.integer.size() - 1, 0);
    for (std::size_t i = 0; i < fir.integer.size(); ++i)
      for (std::size_t j = 0; j < t.integer.size(); ++j)
        c[i + j] += static_cast<Acc>(fir.integer[i]) * t.integer[j];
    constexpr Acc kMaxWeight = Acc{1} << 62;
    for (const Acc ci : c) {
      if (ci >= kMaxWeight || ci <= -kMaxWeight)
        throw InputError(fmt::format("servo matching: axis {}: taps too large", t.axis));
      a.c.push_back(static_cast<std::int64_t>(ci));
    }
    // The weights as doubles, exact below 2^52 (else every sample takes the exact sum).
    a.fast = true;
    for (const std::int64_t ci : a.c) {
      a.cd.push_back(static_cast<double>(ci));
      a.fast = a.fast && std::abs(ci) < (std::int64_t{1} << 52);
    }
    a.hist.assign(2 * a.c.size(), 0);
    a.histd.assign(2 * a.c.size(), 0.0);
    a.equal_run = static_cast<int>(a.c.size());
    axes_.push_back(std::move(a));
  }
}

namespace {

// round_half_away(sum / scale), exactly.
std::int64_t exact_quotient(Acc sum, std::int64_t scale) {
  const Acc mag = (sum < 0 ? -sum : sum) + scale / 2;
  const auto q = static_cast<std::int64_t>(mag / scale);
  return sum < 0 ? -q : q;
}

}  // namespace

void ServoMatch::apply(const BluColumns& cmd, BluColumns& ref, int first, int n) {
  constexpr double kExactBelow = 4503599627370496.0;  // 2^52: integers exact as doubles
  const double scale = static_cast<double>(scale_);
  for (Axis& a : axes_) {
    const int len = static_cast<int>(a.c.size());
    const std::int64_t* in = cmd.v[a.axis];
    std::int64_t* out = ref.v[a.axis];
    for (int i = first; i < first + n; ++i) {
      const std::int64_t x = in[i];
      const auto at = static_cast<std::size_t>(a.head);
      a.equal_run = x == a.hist[at] ? a.equal_run + 1 : 1;
      // The window x[k], x[k−1], … lies in a row from the new head (each slot stored twice).
      a.head = a.head == 0 ? len - 1 : a.head - 1;
      const auto h = static_cast<std::size_t>(a.head);
      a.hist[h] = a.hist[h + static_cast<std::size_t>(len)] = x;
      a.histd[h] = a.histd[h + static_cast<std::size_t>(len)] = static_cast<double>(x);
      if (a.equal_run >= len) {  // settled: the output is the input
        out[i] = x;
        continue;
      }
      // x[k] + Σ_{j≥1} c_j·(x[k−j] − x[k]) / scale: the sum in doubles, with T = Σ|c_j·(x[k−j] −
      // x[k])| bounding its error (at most (len + 4)·2⁻⁵² T); where that leaves the nearest count
      // undecided (the quotient within it of a half: a tie, rounded half away from zero as the
      // filter rounds), or the positions are past 2^52, in 128-bit integers. Both give the same
      // count.
      const std::int64_t* w = a.hist.data() + h;
      if (a.fast && std::abs(static_cast<double>(x)) < kExactBelow) {
        const double* wd = a.histd.data() + h;
        const double* cd = a.cd.data();
        const double xd = wd[0];
        // Four partial sums (the bound holds for any order of summation).
        double s4[4] = {0.0, 0.0, 0.0, 0.0}, b4[4] = {0.0, 0.0, 0.0, 0.0};
        int j = 1;
        for (; j + 4 <= len; j += 4)
          for (int l = 0; l < 4; ++l) {
            const double p = cd[j + l] * (wd[j + l] - xd);
            s4[l] += p;
            b4[l] += std::abs(p);
          }
        for (; j < len; ++j) {
          const double p = cd[j] * (wd[j] - xd);
          s4[0] += p;
          b4[0] += std::abs(p);
        }
        const double sum = (s4[0] + s4[1]) + (s4[2] + s4[3]);
        const double bound = (b4[0] + b4[1]) + (b4[2] + b4[3]);
        const double v = sum / scale;
        const double fl = std::floor(v);
        const double margin = (len + 4) * 0x1p-52 * bound / scale + 0x1p-50 * (std::abs(v) + 1.0);
        if (bound < kExactBelow * scale && std::abs(v) < 0x1p40 &&
            std::abs(v - fl - 0.5) > margin) {
          out[i] = x + static_cast<std::int64_t>(v - fl < 0.5 ? fl : fl + 1.0);
          continue;
        }
      }
      Acc sum = 0;
      for (int j = 1; j < len; ++j)
        sum += static_cast<Acc>(a.c[static_cast<std::size_t>(j)]) * (w[j] - x);
      out[i] = exact_quotient(static_cast<Acc>(x) * scale_ + sum, scale_);
    }
  }
}

int ServoMatch::length() const {
  int n = 0;
  for (const Axis& a : axes_) n = std::max(n, static_cast<int>(a.c.size()));
  return n;
}

bool ServoMatch::settled() const {
  for (const Axis& a : axes_)
    if (a.equal_run < static_cast<int>(a.c.size())) return false;
  return true;
}

}  // namespace gm
