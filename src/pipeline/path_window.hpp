// Contour error: distance from a position to the programmed path over the recent blocks.
#pragma once

#include "common/axis.hpp"
#include "interp/canon.hpp"

#include <array>
#include <cstdint>

namespace gm {

/// Keeps the last few motion blocks (a fixed ring, no allocation) so the distance from the
/// actual position — which lags the command by the Acc/Dec and servo delays — to the nearest
/// point of the programmed path can be measured.
class PathWindow {
 public:
  static constexpr int kCapacity = 64;

  /// `lag_samples`: blocks that ended more than this many samples ago are not searched.
  explicit PathWindow(std::int64_t lag_samples) : lag_samples_(lag_samples) {}

  /// Records that `m` became the current block at sample `k`.
  void push(const Motion& m, std::int64_t k);

  /// Contour error of `p_mm` at sample `k`, mm: the signed radial deviation |p−c|−R (in the
  /// arc's plane; negative = inside) when the nearest block is an arc, else the unsigned
  /// distance to the nearest line segment. 0 when no block has been seen.
  double contour_error_mm(const AxisVec& p_mm, std::int64_t k) const;

  /// Signed radial deviation of `p_mm` from arc `m` (mm); `m` must be an arc.
  static double radial_deviation_mm(const Motion& m, const AxisVec& p_mm);

 private:
  struct Entry {
    Motion motion;
    std::int64_t first_sample = 0;
    std::int64_t last_sample = 0;  ///< the sample the next block started at (or ongoing)
  };
  std::array<Entry, kCapacity> ring_{};
  int count_ = 0;
  int head_ = 0;  ///< index of the newest entry
  std::int64_t lag_samples_;
};

}  // namespace gm
