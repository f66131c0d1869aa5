// Contour error: distance from a position to the programmed path over the recent blocks.
#pragma once

#include "common/axis.hpp"
#include "interp/canon.hpp"
#include "interpolator/geometry.hpp"

#include <array>
#include <cstdint>

namespace gm {

/// Keeps the last few motion blocks (a fixed ring, no allocation) so the distance from the
/// actual position — which lags the command by the Acc/Dec and servo delays — to the nearest
/// point of the programmed path can be measured.
///
/// Per block, push() precomputes what the search needs (its MotionGeometry and a bounding
/// sphere), so a sample costs one bounding-sphere test per block in the window and the exact
/// distance only for the blocks that can still be the nearest. The search starts at the block
/// that was nearest for the previous sample; the result is the same as a plain scan from the
/// newest block (ties go to the newer block).
class PathWindow {
 public:
  static constexpr int kCapacity = 64;  // a power of two

  /// `lag_samples`: blocks that ended more than this many samples ago are not searched.
  explicit PathWindow(std::int64_t lag_samples) : lag_samples_(lag_samples) {}

  /// Records that `m` became the current block at sample `k`.
  void push(const Motion& m, std::int64_t k);

  /// Contour error of `p_mm` at sample `k`, mm: the signed radial deviation |p−c|−R (in the
  /// arc's plane; negative = inside) when the nearest block is an arc, else the unsigned
  /// distance to the nearest line segment. 0 when no block has been seen.
  /// Not const: remembers where the nearest block was, to start the next search there.
  double contour_error_mm(const Vec3& p_mm, std::int64_t k);

  /// The geometry of the block pushed last (the current one), nullptr before the first.
  const MotionGeometry* newest() const {
    return count_ > 0 ? &ring_[static_cast<std::size_t>(head_)].geometry : nullptr;
  }

  /// Signed radial deviation of `p_mm` from arc `m` (mm); `m` must be an arc.
  static double radial_deviation_mm(const Motion& m, const Vec3& p_mm) {
    return MotionGeometry::of(m).radial_deviation_mm(p_mm);
  }

 private:
  struct Entry {
    MotionGeometry geometry;
    std::int64_t first_sample = 0;
    std::int64_t last_sample = 0;     ///< the sample the next block started at (or ongoing)
    Vec3 sphere_c_mm = Vec3::Zero();  ///< a sphere holding every point the distance is to
    double sphere_r_mm = -1.0;        ///< < 0: no bound (helix: the distance is radial only)
    double margin_mm = 0.0;           ///< slack for rounding in the bound test
  };

  std::array<Entry, kCapacity> ring_{};
  int count_ = 0;
  int head_ = 0;      ///< index of the newest entry
  int hint_age_ = 0;  ///< age (0 = newest) of the entry that was nearest last time
  std::int64_t lag_samples_;
};

}  // namespace gm
