// Contour error: distance from a position to the programmed path over the recent blocks.
#pragma once

#include "common/axis.hpp"
#include "motion/canon.hpp"
#include "motion/geometry.hpp"

#include <cstdint>
#include <vector>

namespace gm {

/// Keeps the recent motion blocks (a ring) so the distance from the actual position — which
/// lags the command by the Acc/Dec and servo delays — to the nearest point of the programmed
/// path can be measured. The ring holds every block that can still be nearest: it starts at
/// kInitialCapacity and doubles (up to kMaxCapacity) when the oldest block would be dropped
/// within the lag, as happens when many blocks are shorter than a sample's travel (CAM chords).
/// Memory grows only then; nothing is allocated per sample.
///
/// Per block, push() precomputes what the search needs (its MotionGeometry, the segment of a
/// line and a bounding sphere), so a sample costs one bounding-sphere test per other block in
/// the window and the exact distance only for the blocks that can still be the nearest. The
/// window's end (blocks past the lag) is kept from sample to sample, not rescanned. The search
/// starts at the block that was nearest for the previous sample; the result is the same as a
/// plain scan from the newest block (ties go to the newer block) with
/// MotionGeometry::distance, bit for bit.
class PathWindow {
 public:
  static constexpr int kInitialCapacity = 64;  // powers of two
  static constexpr int kMaxCapacity = 1 << 16;

  /// `lag_samples`: blocks that ended more than this many samples ago are not searched.
  explicit PathWindow(std::int64_t lag_samples)
      : ring_(kInitialCapacity), mask_(kInitialCapacity - 1), lag_samples_(lag_samples) {}

  /// Blocks the ring can hold now.
  int capacity() const { return static_cast<int>(ring_.size()); }
  /// Blocks dropped while still within the lag (only past kMaxCapacity blocks in the lag).

  /// Records that `m` became the current block at sample `k`.
  void push(const Motion& m, std::int64_t k);

  /// Contour error of `p_mm` at sample `k`, mm: the signed radial deviation |p−c|−R (in the
  /// arc's plane; negative = inside) when the nearest block is an arc, else the unsigned
  /// distance to the nearest line segment. 0 when no block has been seen.
  /// Not const: remembers where the nearest block was, to start the next search there.
  double contour_error_mm(const Vec3& p_mm, std::int64_t k) {
    // One block in the window (the common case on long moves): nothing expires, nothing to
    // compare; inline, so such a sample costs the distance alone.
    if (limit_ == 1) return only_block(p_mm);
    return search(p_mm, k);
  }

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
    Segment seg;  ///< lines and rapids: geometry.segment(), formed once per block
  };

  const Entry& at(int age) const { return ring_[static_cast<std::size_t>((head_ - age) & mask_)]; }
  double only_block(const Vec3& p_mm);              ///< contour_error_mm, a window of one
  double search(const Vec3& p_mm, std::int64_t k);  ///< contour_error_mm, any window
  void grow();  ///< doubles the ring, keeping the entries in age order

  std::vector<Entry> ring_;
  int count_ = 0;
  int mask_;      ///< capacity − 1
  int head_ = 0;  ///< index of the newest entry
  /// Ages [0, limit_) are the window: the blocks that ended at most the lag ago (the newest
  /// is ongoing). Ends only recede, so it is kept: push() adds one, a search drops the expired.
  int limit_ = 0;
  int hint_age_ = 0;  ///< age (0 = newest) of the entry that was nearest last time
  std::int64_t lag_samples_;
};

}  // namespace gm
