// FirAccDec::step_block: the FIR over a block of samples, vectorised over time, bit-identical.
//
// Compiled with -ffp-contract=off (src/accdec/CMakeLists.txt): the sums are exact integers, so
// a fused multiply-add would give them too, but the quotient must be the same correctly rounded
// division as step_n's, and no contraction may touch it.
#include "accdec/fir_filter.hpp"

#include "common/rounding.hpp"
#include "common/status.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include <immintrin.h>

namespace gm {

namespace {

// One axis of one block, handed to the kernel. `rel[0 .. L)` is the history (the last L
// relative positions, oldest first) and the kernel writes the block's relative positions after
// it; nothing of the filter's state is changed here, so a block the kernel refuses (a position
// beyond the exact limit) can still run sample by sample.
struct AxisJob {
  const std::int64_t* in = nullptr;  // the block's input column (absolute BLU)
  std::int64_t* out = nullptr;       // the block's output column
  std::int64_t start = 0;
  int n = 0;                     // samples in the block
  int length = 1;                // L = N+1 taps
  std::int64_t* rel = nullptr;   // L + kBlockSamples
  double* rel_real = nullptr;    // L - 1 + kBlockSamples: rel[1 ..] in double, zero padded
  double* sums = nullptr;        // kBlockSamples: Σ_j b_j·rel[k-j], exact integers
  const double* taps = nullptr;  // b_N .. b_0 (oldest first), non-zero from k0 to k1
  int k0 = 0, k1 = 0;
  bool folded = false;           // taps symmetric: pairs of samples added before the multiply
  bool running = false;          // equal taps: the sums are a running sum
  std::int64_t tap = 0;          // running: the common tap
  std::int64_t running_sum = 0;  // running: Σ of the last L relative positions (in and out)
  std::int64_t limit = 0;        // exact_limit()
  std::int64_t b_s = 1;
  double b_s_real = 1.0;
};

constexpr double kQuotientExact = 2251799813685248.0;  // 2^51: see the quotient below
constexpr double kRoundMagic = 6755399441055744.0;     // 1.5·2^52

// acc / den rounded to nearest, halves away from zero (den > 0): step_n's int64 branch.
std::int64_t div_round_half_away(std::int64_t acc, std::int64_t den) {
  std::int64_t q = acc / den;
  const std::int64_t r = acc % den;
  const std::int64_t twice = r < 0 ? -2 * r : 2 * r;
  if (twice >= den) q += acc < 0 ? -1 : 1;
  return q;
}

template <int W>
struct BlockLanes {
  __extension__ typedef double D __attribute__((vector_size(8 * W)));
  __extension__ typedef std::int64_t I __attribute__((vector_size(8 * W)));
  __extension__ typedef std::uint64_t U __attribute__((vector_size(8 * W)));
};

// The helpers below take and return vectors wider than the baseline's registers; they are
// always inlined into functions compiled for the width, so no call ever passes one.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
template <typename V>
__attribute__((always_inline)) inline V load(const void* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <typename V>
__attribute__((always_inline)) inline void store(void* p, const V& v) {
  std::memcpy(p, &v, sizeof v);
}

// The block's exact sums of one axis, W doubles a vector (GCC vector extensions: the caller's
// target decides the instructions). Returns false, having changed nothing but the job's
// scratch, when a relative position of the block is beyond the exact limit.
template <int W>
__attribute__((always_inline)) inline bool axis_sums(AxisJob& j) {
  using D = typename BlockLanes<W>::D;
  using I = typename BlockLanes<W>::I;
  const int L = j.length, n = j.n;
  const int padded = (n + W - 1) / W * W;  // <= kBlockSamples, a multiple of every W
  std::int64_t* const rel = j.rel;
  double* const s = j.sums;

  // The block's relative positions, and whether all are within the limit, W samples at once
  // with adds and ORs, no comparison. In wrapping (unsigned) arithmetic, for any input: with
  // 0 < limit < 2^62, r > limit or r < -limit is exactly when the sign bit of
  // (limit - r) | (r + limit) is set, and in - start wrapped exactly when that of
  // (in ^ start) & (in ^ r) is.
  using U = typename BlockLanes<W>::U;
  const auto start = static_cast<std::uint64_t>(j.start);
  const auto limit = static_cast<std::uint64_t>(j.limit);
  U beyond_v = {};
  int i0 = 0;
  for (; i0 + W <= n; i0 += W) {
    const U in = load<U>(j.in + i0);
    const U r = in - start;
    store(rel + L + i0, r);
    beyond_v |= (limit - r) | (r + limit) | ((in ^ start) & (in ^ r));
  }
  std::uint64_t beyond = 0;
  for (int l = 0; l < W; ++l) beyond |= beyond_v[l];
  for (; i0 < n; ++i0) {
    const auto in = static_cast<std::uint64_t>(j.in[i0]);
    const std::uint64_t r = in - start;
    rel[L + i0] = static_cast<std::int64_t>(r);
    beyond |= (limit - r) | (r + limit) | ((in ^ start) & (in ^ r));
  }
  if ((beyond >> 63) != 0) return false;

  if (j.running) {
    // A prefix sum: S[i] = S[i-1] + rel[i] - rel[i-L], serial (one add a sample, exact in
    // int64); Σ b_j·rel = tap·S is below 2^53 (fast limit), so exact in double too.
    std::int64_t S = j.running_sum;
    for (int i = 0; i < n; ++i) {
      S += rel[L + i] - rel[i];
      s[i] = static_cast<double>(S * j.tap);
    }
    for (int i = n; i < padded; ++i) s[i] = 0.0;
    j.running_sum = S;
  } else {
    // rel_real[k] = rel[k+1]: the L-1 samples before the block, then the block, zero padded,
    // so output i reads rel_real[i + k] for tap k (oldest first).
    double* const x = j.rel_real;
    const int m = L - 1 + n;
    int e = 0;
    for (; e + W <= m; e += W) store(x + e, __builtin_convertvector(load<I>(rel + e + 1), D));
    for (; e < m; ++e) x[e] = static_cast<double>(rel[e + 1]);
    for (; e < L - 1 + padded; ++e) x[e] = 0.0;
    // Σ_k taps[k]·x[i+k] for W outputs at once, four vectors a tap (one broadcast, four
    // independent sums). Every product and partial sum is an integer below 2^53 (the caller
    // checked every |rel| <= limit), so these sums equal step_n's whatever the order.
    const double* const c = j.taps;
    const int k0 = j.k0, k1 = j.k1;
    int i = 0;
    if (j.folded) {
      // c[k0 + p] == c[k1 - p]: x[i+k0+p] + x[i+k1-p] once multiplied (|pair| <= 2·limit and
      // 2·c <= b_s, so still below 2^53); a middle tap when the span is odd.
      const int pairs = (k1 - k0 + 1) / 2;
      const bool middle = (k1 - k0 + 1) % 2 == 1;
      for (; i + 4 * W <= padded; i += 4 * W) {
        D a0 = {}, a1 = {}, a2 = {}, a3 = {};
        const double* lo = x + i + k0;
        const double* hi = x + i + k1;
        for (int p = 0; p < pairs; ++p) {
          const double t = c[k0 + p];
          a0 += t * (load<D>(lo + p) + load<D>(hi - p));
          a1 += t * (load<D>(lo + p + W) + load<D>(hi - p + W));
          a2 += t * (load<D>(lo + p + 2 * W) + load<D>(hi - p + 2 * W));
          a3 += t * (load<D>(lo + p + 3 * W) + load<D>(hi - p + 3 * W));
        }
        if (middle) {
          const double t = c[k0 + pairs];
          a0 += t * load<D>(lo + pairs);
          a1 += t * load<D>(lo + pairs + W);
          a2 += t * load<D>(lo + pairs + 2 * W);
          a3 += t * load<D>(lo + pairs + 3 * W);
        }
        store(s + i, a0);
        store(s + i + W, a1);
        store(s + i + 2 * W, a2);
        store(s + i + 3 * W, a3);
      }
      for (; i < padded; i += W) {
        D a0 = {};
        const double* lo = x + i + k0;
        const double* hi = x + i + k1;
        for (int p = 0; p < pairs; ++p) a0 += c[k0 + p] * (load<D>(lo + p) + load<D>(hi - p));
        if (middle) a0 += c[k0 + pairs] * load<D>(lo + pairs);
        store(s + i, a0);
      }
    } else {
      for (; i + 4 * W <= padded; i += 4 * W) {
        D a0 = {}, a1 = {}, a2 = {}, a3 = {};
        const double* col = x + i;
        for (int k = k0; k <= k1; ++k) {
          const double t = c[k];
          a0 += t * load<D>(col + k);
          a1 += t * load<D>(col + k + W);
          a2 += t * load<D>(col + k + 2 * W);
          a3 += t * load<D>(col + k + 3 * W);
        }
        store(s + i, a0);
        store(s + i + W, a1);
        store(s + i + 2 * W, a2);
        store(s + i + 3 * W, a3);
      }
      for (; i < padded; i += W) {
        D a0 = {};
        for (int k = k0; k <= k1; ++k) a0 += c[k] * load<D>(x + i + k);
        store(s + i, a0);
      }
    }
  }

  return true;
}

// The quotient, as step_n: |sum| < 2^51 -> round_half_away(sum / b_s) on the correctly
// rounded double quotient x (|x| < 2^51, so x - trunc(x) is exact and round_half_away(x) is
// a function of x alone, whichever instructions compute it). Writes q[0 .. padded) and
// returns whether a lane had |sum| >= 2^51: those take step_n's int64 division (finish()).
//
// Portable and AVX2 (no double -> int64 conversion instruction): y = x + 1.5·2^52 lies in
// [2^52, 2^53), where doubles are the integers, so y = 1.5·2^52 + rne(x) exactly (rne: nearest,
// ties to even, the rounding mode), t = y - 1.5·2^52 = rne(x) and f = x - t in [-1/2, 1/2] are
// exact, and the integer rne(x) is y's bit pattern minus 1.5·2^52's. rne and round-half-away
// differ only at halves: +1 when f = 1/2 and x > 0, -1 when f = -1/2 and x < 0.
template <int W>
__attribute__((always_inline)) inline bool quotient_generic(const AxisJob& j, std::int64_t* q) {
  using D = typename BlockLanes<W>::D;
  using I = typename BlockLanes<W>::I;
  const int padded = (j.n + W - 1) / W * W;
  // Unsigned integer lanes: the lanes of a sum >= 2^51, whose results are replaced, may wrap.
  using U = typename BlockLanes<W>::U;
  const D magic = D{} + kRoundMagic;
  const U magic_bits = load<U>(&magic);
  const double b_s = j.b_s_real;
  I wide = {};
  for (int i = 0; i < padded; i += W) {
    const D sum = load<D>(j.sums + i);
    wide |= (sum >= kQuotientExact) | (sum <= -kQuotientExact);
    const D x = sum / b_s;
    const D y = x + kRoundMagic;
    const D f = x - (y - kRoundMagic);
    U r = load<U>(&y) - magic_bits;
    r -= __builtin_convertvector((f == 0.5) & (x > 0.0), U);  // comparisons give -1 (true) or 0
    r += __builtin_convertvector((f == -0.5) & (x < 0.0), U);
    store(q + i, r);
  }
  std::int64_t any_wide = 0;
  for (int l = 0; l < W; ++l) any_wide |= wide[l];
  return any_wide != 0;
}

// AVX-512DQ: round_half_away's own steps, eight lanes at once: i = trunc(x) (vcvttpd2qq),
// f = x - i exact, i + (f >= 1/2) - (f <= -1/2) with mask registers (GCC 12 scalarises the
// generic version's 512-bit comparisons).
__attribute__((target("avx512f,avx512dq,avx512vl,avx512bw"), always_inline)) inline bool
quotient_avx512(const AxisJob& j, std::int64_t* q) {
  const int padded = (j.n + 7) / 8 * 8;
  const __m512d b_s = _mm512_set1_pd(j.b_s_real);
  const __m512d limit = _mm512_set1_pd(kQuotientExact);
  const __m512d half = _mm512_set1_pd(0.5), minus_half = _mm512_set1_pd(-0.5);
  const __m512i one = _mm512_set1_epi64(1);
  __mmask8 wide = 0;
  for (int i = 0; i < padded; i += 8) {
    const __m512d sum = _mm512_loadu_pd(j.sums + i);
    wide |= _mm512_cmp_pd_mask(_mm512_abs_pd(sum), limit, _CMP_GE_OQ);
    const __m512d x = _mm512_div_pd(sum, b_s);
    __m512i r = _mm512_cvttpd_epi64(x);
    const __m512d f = _mm512_sub_pd(x, _mm512_cvtepi64_pd(r));
    r = _mm512_mask_add_epi64(r, _mm512_cmp_pd_mask(f, half, _CMP_GE_OQ), r, one);
    r = _mm512_mask_sub_epi64(r, _mm512_cmp_pd_mask(f, minus_half, _CMP_LE_OQ), r, one);
    _mm512_storeu_si512(q + i, r);
  }
  return wide != 0;
}

// The lanes with |sum| >= 2^51, then out = start + q.
template <int W>
__attribute__((always_inline)) inline void finish(const AxisJob& j, std::int64_t* q, bool wide) {
  if (wide) [[unlikely]] {
    // |sum| <= b_s·limit < 2^53: the double holds the exact integer, int64 arithmetic is exact.
    for (int i = 0; i < j.n; ++i)
      if (!(std::fabs(j.sums[i]) < kQuotientExact))
        q[i] = div_round_half_away(static_cast<std::int64_t>(j.sums[i]), j.b_s);
  }
  using I = typename BlockLanes<W>::I;
  int i = 0;
  for (; i + W <= j.n; i += W) store(j.out + i, load<I>(q + i) + j.start);
  for (; i < j.n; ++i) j.out[i] = j.start + q[i];
}

#pragma GCC diagnostic pop

// One function per instruction set holding the whole loop (one call per axis and block).
__attribute__((target("avx512f,avx512dq,avx512vl,avx512bw"))) bool axis_kernel_avx512(AxisJob& j) {
  if (!axis_sums<8>(j)) return false;
  std::int64_t q[kBlockSamples];
  finish<8>(j, q, quotient_avx512(j, q));
  return true;
}
__attribute__((target("avx2"))) bool axis_kernel_avx2(AxisJob& j) {
  if (!axis_sums<4>(j)) return false;
  std::int64_t q[kBlockSamples];
  finish<4>(j, q, quotient_generic<4>(j, q));
  return true;
}
bool axis_kernel_portable(AxisJob& j) {
  if (!axis_sums<2>(j)) return false;
  std::int64_t q[kBlockSamples];
  finish<2>(j, q, quotient_generic<2>(j, q));
  return true;
}

}  // namespace

void FirAccDec::set_isa_for_testing(Isa isa) {
  isa_ = static_cast<int>(isa) < static_cast<int>(active_isa()) ? isa : active_isa();
}

template <int N>
void FirAccDec::step_block(const BluColumns& in_cols, BluColumns& out_cols, int first, int n) {
  if (first < 0 || n < 1 || first + n > kBlockSamples)  // the scratch holds one block
    throw InputError(fmt::format("FIR Acc/Dec: rows {}..{} of a block (0..{})", first,
                                 first + n - 1, kBlockSamples - 1));
  // Rows first .. first+n-1 of every column, as columns of their own.
  struct Rows {
    const std::int64_t* v[kMaxAxes];
  } in{};
  struct OutRows {
    std::int64_t* v[kMaxAxes];
  } out{};
  for (int a = 0; a < N; ++a) {
    in.v[a] = in_cols.v[a] + first;
    out.v[a] = out_cols.v[a] + first;
  }
  const int L = length_;
  const bool running = structure_ == FirStructure::RunningSum;
  // Fast only if the window before the block is (big_in_window_ counts its last N+1 samples;
  // the kernel checks the block's).
  bool fast = big_in_window_ == 0;
  std::int64_t sums_after[N] = {};
  if (fast) {
    bool (*const kernel)(AxisJob&) = isa_ == Isa::Avx512 ? axis_kernel_avx512
                                     : isa_ == Isa::Avx2 ? axis_kernel_avx2
                                                         : axis_kernel_portable;
    AxisJob job;
    job.n = n;
    job.length = L;
    job.rel = block_rel_.data();
    job.rel_real = block_rel_real_.data();
    job.sums = block_sums_.data();
    job.taps = taps_oldest_first_.data();
    job.k0 = k0_;
    job.k1 = k1_;
    job.folded = structure_ == FirStructure::Symmetric;
    job.running = running;
    job.tap = taps_.front();
    job.limit = fast_limit_;
    job.b_s = b_s_;
    job.b_s_real = b_s_real_;
    for (int a = 0; a < N; ++a) {
      // The last L relative positions, oldest (slot head_ + 1) first.
      int slot = head_ + 1 == L ? 0 : head_ + 1;
      for (int k = 0; k < L; ++k) {
        block_rel_[static_cast<std::size_t>(k)] =
            hist_[static_cast<std::size_t>(slot) * N + static_cast<std::size_t>(a)];
        slot = slot + 1 == L ? 0 : slot + 1;
      }
      job.in = in.v[a];
      job.out = out.v[a];
      job.start = start_[a];
      // Within the fast limit, so the 128-bit running sum fits int64 (|Σ| <= L·limit < 2^53).
      job.running_sum = static_cast<std::int64_t>(running_[static_cast<std::size_t>(a)]);
      if (!kernel(job)) {
        fast = false;
        break;
      }
      sums_after[a] = job.running_sum;
    }
  }
  if (!fast) {
    // A relative position beyond the exact limit: this block sample by sample (step_n keeps
    // its own bookkeeping, including the exact path).
    AxisBlu x = AxisBlu::Zero(), y = AxisBlu::Zero();
    for (int i = 0; i < n; ++i) {
      for (int a = 0; a < N; ++a) x[a] = in.v[a][i];
      step_n<N>(x, y);
      for (int a = 0; a < N; ++a) out.v[a][i] = y[a];
    }
    return;
  }

  // What n calls of step_n would have left. equal_run_: the last sample that differs from its
  // predecessor (the one before the block: last_in_) restarts the count.
  int changed = -1;
  for (int i = n - 1; i >= 0 && changed < 0; --i)
    for (int a = 0; a < N; ++a)
      if (in.v[a][i] != (i > 0 ? in.v[a][i - 1] : last_in_[a])) {
        changed = i;
        break;
      }
  equal_run_ = changed >= 0 ? std::min(L, n - changed) : std::min(L, equal_run_ + n);
  for (int a = 0; a < N; ++a) last_in_[a] = in.v[a][n - 1];
  // The ring: the block's last min(n, L) samples in the slots after head_, as step_n writes
  // them; every one is within the limit, so big_in_window_ stays 0.
  const int first_kept = std::max(0, n - L);
  const int slot0 = static_cast<int>((static_cast<long>(head_) + 1 + first_kept) % L);
  for (int a = 0; a < N; ++a) {
    int slot = slot0;
    double* const col = window_.data() + 4 * 2 * L * (a >> 2) + (a & 3);
    for (int i = first_kept; i < n; ++i) {
      const std::int64_t r = in.v[a][i] - start_[a];
      hist_[static_cast<std::size_t>(slot) * N + static_cast<std::size_t>(a)] = r;
      if (!running) col[4 * slot] = col[4 * (slot + L)] = static_cast<double>(r);
      slot = slot + 1 == L ? 0 : slot + 1;
    }
    if (running) running_[static_cast<std::size_t>(a)] = sums_after[a];
  }
  head_ = static_cast<int>((static_cast<long>(head_) + n) % L);
}

#define GM_FIR_STEP_BLOCK(N) \
  template void FirAccDec::step_block<N>(const BluColumns& in, BluColumns& out, int first, int n);
GM_FOR_EACH_AXIS_COUNT(GM_FIR_STEP_BLOCK)
#undef GM_FIR_STEP_BLOCK

}  // namespace gm
