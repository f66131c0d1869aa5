// The part of an element's tolerance kept for the X/Y/Z servo mismatch, by the speeds it can see.
#pragma once

#include <algorithm>
#include <cmath>

namespace gm {

/// The table differs from the planned chain's output by at most M·V (M = speed_error_s, V the
/// fastest path speed within one chain length before the sample; docs/tolerance.md). An element
/// (corner, arc, run) keeps that for the samples where its own error is active:
///   * uncapped: V is at most the fastest block speed within reach (`v_reach_mm_s`: the blocks
///     less than one chain length of travel before or after the element, each at min(v_max,
///     cap_all); travel counts the blocks at their fastest and the dwells, not the stops);
///   * capped at v: every sample where the element is active has its whole chain window inside
///     the element's zone (the zone lasts a chain length either side of an arc or run, and
///     τ − P either side of a corner active from P to τ after its vertex), so V ≤ v.
/// Never more than `max_mm` (reserve_of(tol): the blocks are capped at max_mm/M, so that much
/// always covers it).
struct MismatchReserve {
  double m_s = 0.0;           ///< M, s (0: no mismatch, every reserve 0)
  double v_reach_mm_s = 0.0;  ///< fastest block speed within reach, mm/s (infinity: unknown)
  double max_mm = 0.0;        ///< reserve_of(tol), mm

  /// The reserve at cap v (`capped`) or without a cap, mm.
  double at(double v_mm_s, bool capped) const {
    const double v = capped ? std::min(v_mm_s, v_reach_mm_s) : v_reach_mm_s;
    return std::min(max_mm, m_s * v);
  }
  /// The reserve once the speed is past where it stops growing (M·v_reach or max_mm), mm.
  double ceiling_mm() const { return std::min(max_mm, m_s * v_reach_mm_s); }

  /// The largest v with a·v² + b·v + at(v, true) <= c (a, b >= 0, not both 0; c >= 0): where a
  /// load that grows as a·v² + b·v reaches the share c with this reserve beside it.
  double root(double a, double b, double c) const {
    if (!(m_s > 0.0)) return quadratic_root(a, b, c);
    const double v = quadratic_root(a, b + m_s, c);  // the reserve still grows: M·v
    if (m_s * v <= ceiling_mm()) return v;
    return quadratic_root(a, b, std::max(0.0, c - ceiling_mm()));
  }
  /// The positive root of a·v² + b·v = c (a, b >= 0, not both 0).
  static double quadratic_root(double a, double b, double c) {
    return a > 0.0 ? (-b + std::sqrt(b * b + 4.0 * a * c)) / (2.0 * a) : c / b;
  }
};

}  // namespace gm
