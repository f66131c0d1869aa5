// G64 Q (LinuxCNC's naive-CAM detector): runs of nearly collinear G1 moves merged into one line.
#pragma once

#include "motion/canon.hpp"

#include <cstddef>
#include <deque>
#include <vector>

namespace gm {

/// Reads canon from `upstream` and hands it on with each run of consecutive straight feed
/// moves (G1, continuous mode, G64 Q > 0 in force) that share feed, tolerances and path mode,
/// move only X, Y and Z, and whose every intermediate vertex lies within Q of the straight line
/// from the run's start to its end, replaced by that one line (LinuxCNC 2.9: "a series of
/// linear XYZ feed moves at the same feed rate that are less than Q- away from being collinear
/// are collapsed into a single linear move"). The merged move keeps the first move's line
/// number and the last one's end point exactly. Anything else (rapids, arcs, G93 moves,
/// dwells, events) ends a run and passes unchanged, in order. A run holds at most
/// `max_run` moves (memory flat: a longer run is emitted and a new one begins).
class NaiveCamMerger : public CanonSource {
 public:
  explicit NaiveCamMerger(CanonSource& upstream, std::size_t max_run = 256)
      : upstream_(upstream), max_run_(max_run) {}
  bool next(Canon& out) override;
  /// Moves handed on.
  std::size_t moves_out() const { return moves_out_; }

 private:
  bool mergeable(const Motion& m) const;
  bool extends(const Motion& m) const;  ///< m continues the run within Q
  void flush();

  CanonSource& upstream_;
  std::size_t max_run_;
  bool active_ = false;
  Motion run_;                     ///< the merged move so far
  std::vector<AxisVec> vertices_;  ///< intermediate vertices of the run (ends before the last)
  std::deque<Canon> ready_;
  Canon scratch_;
  bool ended_ = false;
  std::size_t moves_out_ = 0;
};

}  // namespace gm
