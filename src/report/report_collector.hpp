// Gathers a run's samples into the page's data: decimated time series and the XY paths.
#pragma once

#include "common/axis.hpp"
#include "machine/machine.hpp"
#include "motion/block_sink.hpp"
#include "motion/canon.hpp"
#include "motion/sample_record.hpp"
#include "report/adaptive_bins.hpp"
#include "report/path_simplifier.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace gm::report {

/// The time series of the page, in this order: contour error (BLU), feed override (%), then per
/// machine axis a: velocity (mm/s), acceleration (mm/s²), jerk (mm/s³) of the Acc/Dec output at
/// 2 + 3a, 3 + 3a, 4 + 3a (degrees for rotary axes).
inline constexpr int kContourSeries = 0, kOverrideSeries = 1, kFirstAxisSeries = 2;
inline constexpr int kMaxSeries = kFirstAxisSeries + 3 * kMaxAxes;

/// One column of the time plots: min and max of every series over its samples.
struct SeriesBin {
  std::int64_t k0 = 0;  ///< first sample
  std::array<double, kMaxSeries> lo{}, hi{};
  double worst_abs_contour = -1.0;  ///< largest |contour error| in the column
  int line = 0;                     ///< the source line of that sample
  void merge(const SeriesBin& later);
};

/// One column of the XY path: the first sample's table position and the worst one's.
struct PathBin {
  std::int64_t k0 = 0, k_worst = 0;
  double x0_mm = 0, y0_mm = 0;
  double xw_mm = 0, yw_mm = 0;
  double worst_abs_contour = -1.0;  ///< BLU
  void merge(const PathBin& later);
};

/// A run's BlockSink (or fed every sample and the motions it started); read the bins at the end.
class ReportCollector final : public BlockSink {
 public:
  /// At most `columns` time columns and `path_columns` path columns; the programmed path keeps
  /// at most `path_points` points.
  explicit ReportCollector(const Machine& machine, std::size_t columns = 2048,
                           std::size_t path_columns = 8192, std::size_t path_points = 50000);

  void add(const SampleRecord& s, std::span<const Motion> started);
  /// add() of rows first..count-1 of `b` (contour columns filled), each with the motions
  /// started in it.
  void consume(const SampleBlock& b, int first) override;

  const AdaptiveBins<SeriesBin>& series() const { return series_; }
  const AdaptiveBins<PathBin>& path() const { return path_; }
  const PathSimplifier& programmed() const { return programmed_; }
  int axis_count() const { return axes_; }
  std::string axis_letters() const { return layout_.letters(); }
  bool has_xy() const { return x_ >= 0 && y_ >= 0; }
  double period_s() const { return period_s_; }
  double max_abs_contour_blu() const { return max_abs_contour_; }
  /// The source lines the columns name (sorted, unique).
  std::vector<int> lines() const;

 private:
  void add_motion(const Motion& m);

  AxisLayout layout_;
  int axes_ = 0;
  int x_ = -1, y_ = -1;  ///< machine axis of X and Y, or -1
  MachineVec blu_mm_;
  double period_s_;
  AdaptiveBins<SeriesBin> series_;
  AdaptiveBins<PathBin> path_;
  PathSimplifier programmed_;
  SampleRecord row_;  ///< consume()'s record of a row
  bool first_ = true;
  AxisBlu prev_ref_ = AxisBlu::Zero();
  MachineVec prev_v_ = MachineVec::Zero(), prev_a_ = MachineVec::Zero();
  double max_abs_contour_ = 0.0;
  bool have_end_ = false;
  double end_x_ = 0, end_y_ = 0;
  bool end_rapid_ = false;
};

}  // namespace gm::report
