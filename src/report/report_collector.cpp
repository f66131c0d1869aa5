// Gathers a run's samples into the page's data: decimated time series and the XY paths.
#include "report/report_collector.hpp"

#include "motion/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gm::report {

void SeriesBin::merge(const SeriesBin& later) {
  for (std::size_t i = 0; i < lo.size(); ++i) {
    lo[i] = std::min(lo[i], later.lo[i]);
    hi[i] = std::max(hi[i], later.hi[i]);
  }
  if (later.worst_abs_contour > worst_abs_contour) {
    worst_abs_contour = later.worst_abs_contour;
    line = later.line;
  }
}

void PathBin::merge(const PathBin& later) {
  if (later.worst_abs_contour > worst_abs_contour) {
    worst_abs_contour = later.worst_abs_contour;
    k_worst = later.k_worst;
    xw_mm = later.xw_mm;
    yw_mm = later.yw_mm;
  }
}

ReportCollector::ReportCollector(const Machine& machine, std::size_t columns,
                                 std::size_t path_columns, std::size_t path_points)
    : layout_(machine.layout),
      axes_(machine.axis_count()),
      blu_mm_(machine.blu_mm()),
      period_s_(machine.period_s),
      series_(columns),
      path_(path_columns),
      programmed_(path_points) {
  for (int a = 0; a < axes_; ++a) {
    if (layout_.program(a) == 0) x_ = a;
    if (layout_.program(a) == 1) y_ = a;
  }
}

void ReportCollector::add_motion(const Motion& m) {
  const bool rapid = m.kind == MotionKind::Rapid;
  const double sx = m.start_mm[0], sy = m.start_mm[1];
  const bool jump = !have_end_ || sx != end_x_ || sy != end_y_ || rapid != end_rapid_;
  if (jump) programmed_.add(sx, sy, true, rapid);
  if (m.kind == MotionKind::Arc) {
    const MotionGeometry g = MotionGeometry::of(m);
    // Chords of at most 5 degrees: under 0.1 % of the radius from the arc.
    const int n = std::max(
        1, static_cast<int>(std::ceil(std::abs(g.sweep_rad) / (5.0 * std::numbers::pi / 180.0))));
    for (int i = 1; i <= n; ++i) {
      const AxisVec p = g.at_fraction(static_cast<double>(i) / n);
      programmed_.add(p[0], p[1], false, rapid);
    }
  } else {
    programmed_.add(m.end_mm[0], m.end_mm[1], false, rapid);
  }
  have_end_ = true;
  end_x_ = m.end_mm[0];
  end_y_ = m.end_mm[1];
  end_rapid_ = rapid;
}

void ReportCollector::consume(const SampleBlock& b, int first) {
  std::size_t m = 0;
  while (m < b.motions.size() && b.motion_row[m] < first) ++m;
  with_axis_count(axes_, [&](auto n) {
    for (int i = first; i < b.count; ++i) {
      const std::size_t m0 = m;
      while (m < b.motions.size() && b.motion_row[m] == i) ++m;
      b.record<decltype(n)::value>(i, period_s_, row_);
      row_.contour_err_blu = b.contour_err_blu[i];
      row_.arc_ref_dev_blu = b.arc_ref_dev_blu[i];
      row_.arc_enc_dev_blu = b.arc_enc_dev_blu[i];
      add(row_, std::span<const Motion>(b.motions.data() + m0, m - m0));
    }
  });
}

void ReportCollector::add(const SampleRecord& s, std::span<const Motion> started) {
  for (const Motion& m : started) add_motion(m);
  if (first_) prev_ref_ = s.ref_blu;
  SeriesBin b;
  b.k0 = s.k;
  const double ce = s.contour_err_blu;
  const double abs_ce = std::isfinite(ce) ? std::abs(ce) : 0.0;
  b.lo[kContourSeries] = b.hi[kContourSeries] = std::isfinite(ce) ? ce : 0.0;
  b.lo[kOverrideSeries] = b.hi[kOverrideSeries] = s.feed_scale * 100.0;
  for (int a = 0; a < axes_; ++a) {
    const double v = static_cast<double>(s.ref_blu[a] - prev_ref_[a]) * blu_mm_[a] / period_s_;
    const double acc = first_ ? 0.0 : (v - prev_v_[a]) / period_s_;
    const double jerk = first_ ? 0.0 : (acc - prev_a_[a]) / period_s_;
    const auto i = static_cast<std::size_t>(kFirstAxisSeries + 3 * a);
    b.lo[i] = b.hi[i] = v;
    b.lo[i + 1] = b.hi[i + 1] = acc;
    b.lo[i + 2] = b.hi[i + 2] = jerk;
    prev_v_[a] = v;
    prev_a_[a] = acc;
  }
  prev_ref_ = s.ref_blu;
  first_ = false;
  b.worst_abs_contour = abs_ce;
  b.line = s.line;
  series_.add(b);
  max_abs_contour_ = std::max(max_abs_contour_, abs_ce);

  if (has_xy()) {
    PathBin p;
    p.k0 = p.k_worst = s.k;
    p.x0_mm = p.xw_mm = s.table_blu[x_] * blu_mm_[x_];
    p.y0_mm = p.yw_mm = s.table_blu[y_] * blu_mm_[y_];
    p.worst_abs_contour = abs_ce;
    path_.add(p);
  }
}

std::vector<int> ReportCollector::lines() const {
  std::vector<int> v;
  v.reserve(series_.bins().size());
  for (const SeriesBin& b : series_.bins())
    if (b.line > 0) v.push_back(b.line);
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

}  // namespace gm::report
