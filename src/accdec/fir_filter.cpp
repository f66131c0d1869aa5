// FirAccDec: exact integer FIR on relative positions (direct, symmetric and running-sum forms).
#include "accdec/fir_filter.hpp"

#include "common/rounding.hpp"
#include "common/status.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace gm {

namespace {

// acc / den rounded to nearest, halves away from zero (den > 0).
template <typename Acc>
std::int64_t div_round_half_away(Acc acc, Acc den) {
  Acc q = acc / den;
  const Acc r = acc % den;
  const Acc twice = r < 0 ? -2 * r : 2 * r;
  if (twice >= den) q += acc < 0 ? -1 : 1;
  return static_cast<std::int64_t>(q);
}

}  // namespace

namespace {

__extension__ typedef double Lanes __attribute__((vector_size(32)));

// acc += t·col (columns are 16-byte aligned only, hence the copies; by reference, not by value,
// so no function passes a 32-byte vector in registers without AVX).
__attribute__((always_inline)) inline void add_product(Lanes& acc, double t, const double* col) {
  Lanes x;
  std::memcpy(&x, col, sizeof x);
  acc += t * x;
}
// acc += t·(lo + hi): a mirrored pair of columns with equal taps.
__attribute__((always_inline)) inline void add_pair_product(Lanes& acc, double t, const double* lo,
                                                            const double* hi) {
  Lanes x, y;
  std::memcpy(&x, lo, sizeof x);
  std::memcpy(&y, hi, sizeof y);
  acc += t * (x + y);
}

// Σ_j tap[j]·col[4j .. 4j+3] over n columns, four lanes (axes) at a time, into out[0..3].
// `folded`: the taps are symmetric (tap[j] = tap[n-1-j]), so pairs of columns are added first
// and each pair multiplied once. Every product and partial sum is an integer below 2^53 (the
// caller's condition), so the result does not depend on the order of the additions: two
// accumulators, and the fold, give the same sums as one left-to-right loop. GCC/Clang vector
// extensions, so the lane width follows the target the caller is compiled for.
__attribute__((always_inline)) inline void dot4(const double* col, const double* tap, int n,
                                                bool folded, double* out) {
  Lanes acc0 = {0.0, 0.0, 0.0, 0.0}, acc1 = acc0;
  if (folded) {
    const int pairs = n / 2;
    const double* hi = col + 4 * (n - 1);
    int j = 0;
    for (; j + 1 < pairs; j += 2) {
      add_pair_product(acc0, tap[j], col + 4 * j, hi - 4 * j);
      add_pair_product(acc1, tap[j + 1], col + 4 * (j + 1), hi - 4 * (j + 1));
    }
    for (; j < pairs; ++j) add_pair_product(acc0, tap[j], col + 4 * j, hi - 4 * j);
    if (n % 2 == 1) add_product(acc1, tap[pairs], col + 4 * pairs);
  } else {
    int j = 0;
    for (; j + 1 < n; j += 2) {
      add_product(acc0, tap[j], col + 4 * j);
      add_product(acc1, tap[j + 1], col + 4 * (j + 1));
    }
    if (j < n) add_product(acc0, tap[j], col + 4 * j);
  }
  const Lanes acc = acc0 + acc1;
  std::memcpy(out, &acc, sizeof acc);
}
__attribute__((target("avx2"))) void dot4_avx2(const double* col, const double* tap, int n,
                                               bool folded, double* out) {
  dot4(col, tap, n, folded, out);
}
void dot4_baseline(const double* col, const double* tap, int n, bool folded, double* out) {
  dot4(col, tap, n, folded, out);
}

// Asked once per filter: an explicit check rather than an ifunc (target_clones), whose
// resolver runs before the sanitizers' runtimes are up.
bool cpu_has_avx2() {
  static const bool yes = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return yes;
}

}  // namespace

FirAccDec::FirAccDec(const Taps& taps, const AxisBlu& start_pos_blu, FirStructure structure,
                     int axes)
    : taps_(taps.integer), start_(start_pos_blu), last_in_(start_pos_blu) {
  if (axes < 1 || axes > kMaxAxes)
    throw InputError(fmt::format("FIR Acc/Dec: {} axes (1..{})", axes, kMaxAxes));
  axes_ = axes;
  groups_ = (axes + 3) / 4;
  if (taps_.empty()) throw InputError(fmt::format("profile '{}': no integer taps", taps.profile));
  std::int64_t sum = 0;
  for (std::size_t i = 0; i < taps_.size(); ++i) {
    if (taps_[i] < 0)
      throw InputError(
          fmt::format("profile '{}': integer tap b{} = {} is negative", taps.profile, i, taps_[i]));
    sum += taps_[i];
  }
  if (sum <= 0)
    throw InputError(fmt::format("profile '{}': b_s = {} must be > 0", taps.profile, sum));
  b_s_ = sum;
  b_s_real_ = static_cast<double>(sum);
  length_ = static_cast<int>(taps_.size());
  equal_run_ = length_;  // the history is the start position repeated

  const bool all_equal =
      std::all_of(taps_.begin(), taps_.end(), [&](std::int64_t b) { return b == taps_.front(); });
  const bool symmetric = std::equal(taps_.begin(), taps_.end(), taps_.rbegin());
  if (structure == FirStructure::Auto)
    structure = all_equal   ? FirStructure::RunningSum
                : symmetric ? FirStructure::Symmetric
                            : FirStructure::Direct;
  if (structure == FirStructure::RunningSum && !all_equal)
    throw InputError(
        fmt::format("profile '{}': the running-sum form needs equal taps", taps.profile));
  if (structure == FirStructure::Symmetric && !symmetric)
    throw InputError(
        fmt::format("profile '{}': the symmetric form needs b_i = b_(N-i)", taps.profile));
  structure_ = structure;
  hist_.assign(static_cast<std::size_t>(length_) * static_cast<std::size_t>(axes_), 0);
  running_.fill(0);
  window_.setZero(4, 2 * length_ * groups_);
  taps_oldest_first_.assign(taps_.rbegin(), taps_.rend());
  fast_limit_ = ((std::int64_t{1} << 53) - 1) / b_s_;
  use_avx2_ = cpu_has_avx2();
  isa_ = active_isa();
  // step_block skips zero end taps (b_0 = 0 in many profiles); symmetric taps stay symmetric.
  k0_ = static_cast<int>(std::find_if(taps_oldest_first_.begin(), taps_oldest_first_.end(),
                                      [](double b) { return b != 0.0; }) -
                         taps_oldest_first_.begin());
  k1_ = length_ - 1 -
        static_cast<int>(std::find_if(taps_oldest_first_.rbegin(), taps_oldest_first_.rend(),
                                      [](double b) { return b != 0.0; }) -
                         taps_oldest_first_.rbegin());
  block_rel_.assign(static_cast<std::size_t>(length_ + kBlockSamples), 0);
  block_rel_real_.assign(static_cast<std::size_t>(length_ - 1 + kBlockSamples), 0.0);
  block_sums_.assign(static_cast<std::size_t>(kBlockSamples), 0.0);
}

FirAccDec::Acc FirAccDec::convolve(int axis) const {
  const int n = length_;
  // Relative position i samples ago.
  auto at = [&](int i) -> Acc {
    int slot = head_ - i;
    if (slot < 0) slot += n;
    return hist_[static_cast<std::size_t>(slot) * static_cast<std::size_t>(axes_) +
                 static_cast<std::size_t>(axis)];
  };
  Acc acc = 0;
  if (structure_ == FirStructure::Symmetric) {
    const int half = n / 2;  // pairs (i, N-i) for i < half; middle tap when n is odd
    for (int i = 0; i < half; ++i)
      acc += Acc{taps_[static_cast<std::size_t>(i)]} * (at(i) + at(n - 1 - i));
    if (n % 2 == 1) acc += Acc{taps_[static_cast<std::size_t>(half)]} * at(half);
  } else {
    for (int i = 0; i < n; ++i) acc += Acc{taps_[static_cast<std::size_t>(i)]} * at(i);
  }
  return acc;
}

// AVX2 when the CPU has it (one 4-lane operation per tap pair), SSE2 otherwise; the sums are
// exact integers either way, so the result does not depend on which one runs.
void FirAccDec::convolve_fast(double* sums, int groups) const {
  const bool folded = structure_ == FirStructure::Symmetric;
  for (int g = 0; g < groups; ++g) {
    // The oldest sample of group g's window.
    const double* col = window_.data() + 4 * (2 * length_ * g + head_ + 1);
    if (use_avx2_)
      dot4_avx2(col, taps_oldest_first_.data(), length_, folded, sums + 4 * g);
    else
      dot4_baseline(col, taps_oldest_first_.data(), length_, folded, sums + 4 * g);
  }
}

void FirAccDec::step(const AxisBlu& in_pos_blu, AxisBlu& out_pos_blu) {
  with_axis_count(axes_, [&](auto n) { step_n<decltype(n)::value>(in_pos_blu, out_pos_blu); });
}

template <int N>
void FirAccDec::step_n(const AxisBlu& in_pos_blu, AxisBlu& out_pos_blu) {
  constexpr int axes = N;  // == axes_
  const auto in = in_pos_blu.head<N>();
  if (in == last_in_.head<N>()) {
    if (equal_run_ < length_) ++equal_run_;
  } else {
    equal_run_ = 1;
    last_in_.head<N>() = in;
  }
  head_ = head_ + 1 == length_ ? 0 : head_ + 1;  // the oldest slot becomes the newest
  const bool running = structure_ == FirStructure::RunningSum;
  for (int a = 0; a < axes; ++a) {
    const std::size_t idx = static_cast<std::size_t>(head_) * static_cast<std::size_t>(axes) +
                            static_cast<std::size_t>(a);
    std::int64_t rel;
    if (__builtin_sub_overflow(in_pos_blu[a], start_[a], &rel)) [[unlikely]]
      throw InputError(
          fmt::format("FIR Acc/Dec: axis {} at {} BLU is beyond int64 from its "
                      "start at {} BLU",
                      a, in_pos_blu[a], start_[a]));
    const std::int64_t old = hist_[idx];
    big_in_window_ += static_cast<int>(rel > fast_limit_ || rel < -fast_limit_) -
                      static_cast<int>(old > fast_limit_ || old < -fast_limit_);
    hist_[idx] = rel;
    if (running) {
      running_[static_cast<std::size_t>(a)] += Acc{rel} - Acc{old};
    } else {
      const int col = 2 * length_ * (a >> 2) + head_;
      window_(a & 3, col) = window_(a & 3, col + length_) = static_cast<double>(rel);
    }
  }
  const bool fast = big_in_window_ == 0;  // every |rel| in the window <= fast_limit_
  constexpr int kGroupsN = (N + 3) / 4;
  double sums[4 * kGroupsN] = {};
  if (fast && !running) convolve_fast(sums, kGroupsN);
  for (int a = 0; a < axes; ++a) {
    std::int64_t q;
    if (fast && !running && std::fabs(sums[a]) < kQuotientExact) {
      // |sum| < 2^51: the double quotient lies within 1/(4 b_s) of the exact one, and the
      // exact one is at least 1/(2 b_s) from any half-integer it does not equal (a half is
      // representable here), so rounding the double quotient rounds the exact one.
      q = round_half_away(sums[a] / b_s_real_);
    } else if (fast) {
      // |sum| <= b_s * fast_limit_ < 2^53: int64 arithmetic is exact.
      const std::int64_t sum =
          running ? static_cast<std::int64_t>(running_[static_cast<std::size_t>(a)]) * taps_.front()
                  : static_cast<std::int64_t>(sums[a]);
      q = div_round_half_away<std::int64_t>(sum, b_s_);
    } else {
      const Acc acc =
          running ? running_[static_cast<std::size_t>(a)] * Acc{taps_.front()} : convolve(a);
      q = div_round_half_away(acc, Acc{b_s_});
    }
    out_pos_blu[a] = start_[a] + q;
  }
}

#define GM_FIR_STEP_N(N) \
  template void FirAccDec::step_n<N>(const AxisBlu& in_pos_blu, AxisBlu& out_pos_blu);
GM_FOR_EACH_AXIS_COUNT(GM_FIR_STEP_N)
#undef GM_FIR_STEP_N

}  // namespace gm
