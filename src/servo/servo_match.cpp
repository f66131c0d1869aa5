// Servo matching: an axis's reference shaped so that its servo responds as the reference axis's.
#include "servo/servo_match.hpp"

#include "common/status.hpp"

#include <fmt/format.h>

#include <algorithm>
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
    a.c.assign(fir.integer.size() + t.integer.size() - 1, 0);
    for (std::size_t i = 0; i < fir.integer.size(); ++i)
      for (std::size_t j = 0; j < t.integer.size(); ++j)
        a.c[i + j] += fir.integer[i] * t.integer[j];
    a.hist.assign(a.c.size(), 0);
    a.equal_run = static_cast<int>(a.c.size());
    axes_.push_back(std::move(a));
  }
}

void ServoMatch::apply(const BluColumns& cmd, BluColumns& ref, int first, int n) {
  for (Axis& a : axes_) {
    const int len = static_cast<int>(a.hist.size());
    const std::int64_t* c = a.c.data();
    const std::int64_t* in = cmd.v[a.axis];
    std::int64_t* out = ref.v[a.axis];
    for (int i = first; i < first + n; ++i) {
      const std::int64_t x = in[i];
      a.equal_run = x == a.hist[static_cast<std::size_t>(a.head)] ? a.equal_run + 1 : 1;
      a.head = a.head + 1 == len ? 0 : a.head + 1;
      a.hist[static_cast<std::size_t>(a.head)] = x;
      if (a.equal_run >= len) {  // settled: the output is the input
        out[i] = x;
        continue;
      }
      // Σ_{i≥1} c_i·(x[k−i] − x[k]) in 128 bits (count differences times b_s·2^24 < 2^60).
      Acc sum = 0;
      int slot = a.head;
      for (int j = 1; j < len; ++j) {
        slot = slot == 0 ? len - 1 : slot - 1;
        sum += static_cast<Acc>(c[j]) * (a.hist[static_cast<std::size_t>(slot)] - x);
      }
      // round_half_away(sum / scale_), exactly.
      const Acc mag = (sum < 0 ? -sum : sum) + scale_ / 2;
      const auto q = static_cast<std::int64_t>(mag / scale_);
      out[i] = x + (sum < 0 ? -q : q);
    }
  }
}

int ServoMatch::length() const {
  int n = 0;
  for (const Axis& a : axes_) n = std::max(n, static_cast<int>(a.hist.size()));
  return n;
}

bool ServoMatch::settled() const {
  for (const Axis& a : axes_)
    if (a.equal_run < static_cast<int>(a.hist.size())) return false;
  return true;
}

}  // namespace gm
