// CornerMomentGrid: the corner moments D(j·T), j = 0..N, bit for bit as FilterMoments computes
// them.
#pragma once

#include "planner/filter_moments.hpp"

#include <vector>

namespace gm {

/// D(P) at the pauses P = j·T, j = 0..N, that the planner tries at a corner, each computed on
/// first use. Every value is the very double `FilterMoments::corner_moment_s(0.5·(2j)·T)` returns:
/// the same bisection runs, mid after mid, and only how each comparison A(mid) > B(mid − P) is
/// decided differently. A and B are sums over the weights that are piecewise linear in t with
/// breakpoints at the samples; running sums over the weights (suffix sums for A, prefix sums for
/// B) give each in O(log N) with a bound on its distance from the reference's floating-point sum
/// (its rounding and theirs). When the two intervals are apart, the reference's comparison has
/// that outcome; when they overlap (the last few mids, within rounding of the crossing), the
/// reference's own sums decide. The value at the end is the reference's own min(A, B). So the
/// path of mids and the result are the reference's, and a bisection costs a few passes over the
/// weights instead of two per mid (≈ 100).
class CornerMomentGrid {
 public:
  explicit CornerMomentGrid(const FilterMoments& filter);

  /// N + 1: pauses 0, T, …, N·T.
  int size() const { return static_cast<int>(d_.size()); }
  /// D(j·T), s.
  double at(int j);
  /// filter.corner_moment_s(pause_s), the same double, for any pause.
  double moment_s(double pause_s) const;

 private:
  struct Bounded {
    double value;  ///< the sum in running sums
    double error;  ///< bound on |value − the reference's floating-point sum|
  };
  /// Bound on the distance of a sum of `terms` terms from the reference's, per unit of Σ|terms|.
  static double slack(std::size_t terms);
  Bounded pre(double t) const;        ///< A(t) (pre_moment) or A⁺(t) (pre_pos)
  Bounded post(double t) const;       ///< B(t) (post_moment) or B⁺(t) (post_pos)
  double exact_pre(double t) const;   ///< the reference's A(t) or A⁺(t), every bit
  double exact_post(double t) const;  ///< the reference's B(t) or B⁺(t), every bit
  /// The reference's comparison pre(t) > post(t_post), certified or by its own sums.
  bool pre_exceeds(double t, double t_post) const;

  FilterMoments f_;
  bool signed_ = false;  ///< the chain over- or undershoots: A⁺ and B⁺
  // Unsigned chain: c_i = i·T (as the reference computes it), suffix and prefix sums of h_i and
  // h_i·c_i and of their absolute values.
  std::vector<double> c_, suf_h_, suf_hc_, suf_abs_h_, suf_abs_hc_;
  std::vector<double> pre_h_, pre_hc_, pre_abs_h_, pre_abs_hc_;
  // Signed chain: A⁺'s intervals ((k−1)T, kT] with their max(C_k, 0) and the suffix sums of the
  // whole-interval terms; B⁺'s intervals (kT, (k+1)T] with max(S_k, 0) and prefix sums.
  std::vector<double> a_lo_, a_hi_, a_c_, a_suf_;
  std::vector<double> b_lo_, b_hi_, b_s_, b_pre_;
  std::vector<double> d_;
  std::vector<char> known_;
};

}  // namespace gm
