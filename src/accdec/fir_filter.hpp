// The FIR Acc/Dec filter (Eq. 8, Step 3): integer taps applied to all axes in integer arithmetic.
#pragma once

#include "accdec/taps.hpp"
#include "common/axis.hpp"
#include "common/block_columns.hpp"
#include "common/isa.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace gm {

/// How the convolution is evaluated; all give bit-identical outputs (exact integer sums).
enum class FirStructure {
  Auto,       ///< RunningSum if all taps are equal, else Symmetric if b_i = b_{N-i}, else Direct
  Direct,     ///< Σ b_i·P[k-i] (Fig. 6a)
  Symmetric,  ///< Σ b_i·(P[k-i] + P[k-N+i]) (+ middle tap), half the multiplies (Fig. 6b/6c)
  RunningSum  ///< equal taps only: S[k] = S[k-1] + P[k] - P[k-N-1], output b·S[k]/b_s
};

/// Per-axis FIR Acc/Dec on positions. By Eq. 12 the position dynamics equal the velocity
/// dynamics, so the filter runs on positions relative to the start position:
///   out[k] = start + round_half_away( Σ_i b_i·(in[k-i] - start) / b_s ),
/// with the history before the first sample equal to the start. The sum is exact, so once the
/// last N+1 inputs are equal to P the output is exactly P. Velocity |Δout| never exceeds the
/// input's peak |Δin| + 1 BLU (convex combination + rounding).
///
/// Two evaluations, chosen per sample, give the same integer sum:
///  - fast: while every relative position in the window is at most `exact_limit()` =
///    (2^53 − 1) / b_s in magnitude, every product and partial sum is an integer below 2^53,
///    so double arithmetic is exact; the axes run side by side in 4-lane vectors (one group of
///    four axes per vector: one for up to four axes, three for nine) over a contiguous
///    (mirrored) window, which the compiler vectorises;
///  - exact: otherwise, __int128 sums over the integer ring.
/// Valid for positions with |in - start| < 2^62 BLU. Allocates only in the constructor.
class FirAccDec {
 public:
  /// `taps.integer` must be non-empty with all taps >= 0 and b_s > 0 (else gm::InputError).
  /// `axes`: how many entries of the position vectors are filtered (1..kMaxAxes).
  FirAccDec(const Taps& taps, const AxisBlu& start_pos_blu,
            FirStructure structure = FirStructure::Auto, int axes = 3);

  /// One sample: input = the interpolator's commanded position (BLU); output = the smoothed
  /// reference position (BLU).
  /// Entries past the filter's axis count are neither read nor written.
  void step(const AxisBlu& in_pos_blu, AxisBlu& out_pos_blu);
  /// step() with the axis count N (== the count given to the constructor) known at compile
  /// time: what the pipeline calls every sample (instantiated for GM_FOR_EACH_AXIS_COUNT).
  template <int N>
  void step_n(const AxisBlu& in_pos_blu, AxisBlu& out_pos_blu);
  /// n consecutive samples (1..kBlockSamples) at once: out.v[a][i] for a < N, i < n is what n
  /// calls of step_n<N> on in.v[.][i] give, bit for bit, and the filter is left as they leave
  /// it (any mix of step_n and step_block calls gives step_n's outputs). Per axis the outputs
  /// are computed vectorised over time (8 or 4 samples a vector, see isa()) while every relative
  /// position of the window (the last N+1 samples before the block and the block) is within
  /// exact_limit(); otherwise this block runs step_n sample by sample. Allocates nothing;
  /// nothing of `out` past sample n or axis N is written; n outside 1..kBlockSamples throws
  /// gm::InputError. Instantiated for GM_FOR_EACH_AXIS_COUNT.
  template <int N>
  void step_block(const BluColumns& in, BluColumns& out, int n) {
    step_block<N>(in, out, 0, n);
  }
  /// The same over rows first .. first+n-1 of the columns (first + n <= kBlockSamples): the
  /// filter sees those rows as its next n samples.
  template <int N>
  void step_block(const BluColumns& in, BluColumns& out, int first, int n);

  /// True when the last N+1 inputs are equal (then output == input exactly).
  bool settled() const { return equal_run_ >= length_; }
  /// N+1.
  int length() const { return length_; }
  /// The structure in use (after resolving Auto).
  FirStructure structure() const { return structure_; }
  /// Largest |in - start| (BLU) the fast double evaluation handles exactly.
  std::int64_t exact_limit() const { return fast_limit_; }
  /// The instruction set step_block's kernel runs: gm::active_isa() unless lowered for a test.
  Isa isa() const { return isa_; }
  /// Tests only: run step_block's kernel with `isa`, capped at gm::active_isa() (a higher set
  /// could fault on this CPU). Every set gives the same outputs; this is how the tests check it
  /// in one process.
  void set_isa_for_testing(Isa isa);

 private:
  __extension__ using Acc = __int128;

  Acc convolve(int axis) const;  // Σ b_i·hist[k-i] for the current head (exact path)
  static constexpr int kGroups = (kMaxAxes + 3) / 4;  // 4-lane groups for the most axes
  // The same sums (exact integers in double), fast path: sums[4g .. 4g+3] for groups g < groups.
  void convolve_fast(double* sums, int groups) const;

  std::vector<std::int64_t> taps_;  // integer taps b_0..b_N
  std::int64_t b_s_ = 1;
  double b_s_real_ = 1.0;  // b_s_ as a double (exact whenever a fast sum is non-zero)
  static constexpr double kQuotientExact = 2251799813685248.0;  // 2^51: see step()
  int length_ = 1;
  int axes_ = 3;
  int groups_ = 1;  // 4-lane groups in use: (axes_ + 3) / 4
  FirStructure structure_ = FirStructure::Direct;
  AxisBlu start_ = AxisBlu::Zero();
  AxisBlu last_in_ = AxisBlu::Zero();
  int equal_run_ = 0;                    // consecutive equal inputs, counting the implicit history
  std::vector<std::int64_t> hist_;       // ring: hist_[slot*axes_ + axis] = in - start
  int head_ = 0;                         // slot of the newest sample
  std::array<Acc, kMaxAxes> running_{};  // RunningSum: Σ of the last N+1 relative positions
  // Fast path: the window as 4-lane columns (axes 4g .. 4g+3 of group g, unused lanes 0), group
  // g in columns g·2(N+1) .. (g+1)·2(N+1) - 1; each sample stored at slot and slot + N+1, so
  // the last N+1 samples are columns head_+1 .. head_+N+1 of the group, oldest first.
  Eigen::Matrix<double, 4, Eigen::Dynamic> window_;
  std::vector<double> taps_oldest_first_;  // b_N .. b_0
  std::int64_t fast_limit_ = 0;            // (2^53 - 1) / b_s
  int big_in_window_ = 0;                  // samples in the window with |rel| > fast_limit_
  bool use_avx2_ = false;                  // the CPU runs the AVX2 version of the fast path
  // step_block: the kernel's instruction set; the non-zero taps k0_..k1_ of taps_oldest_first_
  // (many profiles have b_0 = b_N = 0); one axis's scratch, reused axis after axis: the last
  // N+1 relative positions (oldest first) then the block's, in int64 and (from the second on)
  // in double, and the block's exact sums. Sized in the constructor.
  Isa isa_ = Isa::Portable;
  int k0_ = 0, k1_ = 0;
  std::vector<std::int64_t> block_rel_;
  std::vector<double> block_rel_real_;
  std::vector<double> block_sums_;
};

}  // namespace gm
