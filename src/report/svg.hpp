// SVG building blocks for the report: linear scales, nice ticks, polylines, min/max bands, axes.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace gm::report {

/// Maps [d0, d1] (data) linearly onto [p0, p1] (SVG user units); a degenerate data range maps
/// to the middle of the pixel range.
struct Scale {
  double d0 = 0, d1 = 1, p0 = 0, p1 = 1;
  double operator()(double v) const {
    return d1 == d0 ? (p0 + p1) / 2 : p0 + (v - d0) * (p1 - p0) / (d1 - d0);
  }
};

/// A coordinate with `decimals` digits after the point, without a trailing "-0".
std::string coord(double v, int decimals = 2);

/// "x,y x,y ..." for points already in SVG units.
std::string points_attr(const std::vector<std::pair<double, double>>& pts, int decimals = 2);

/// About `n` round tick values (1, 2, 5 × 10^k steps) covering [lo, hi].
std::vector<double> nice_ticks(double lo, double hi, int n = 5);

/// A data range widened so that it is not empty and has a little room above and below.
std::pair<double, double> padded_range(double lo, double hi);

/// Short text for a tick value (general format, 4 significant digits).
std::string tick_label(double v);

/// A chart's frame: the plot rectangle in a viewBox of `width` x `height`, ticks and labels
/// on both axes for the data ranges of `x` and `y`, the y axis titled `y_title`.
struct Frame {
  double width = 1000, height = 170;
  double left = 64, right = 10, top = 8, bottom = 24;
  Scale x, y;
  /// The frame's scales for the data ranges [x0, x1] and [y0, y1].
  static Frame of(double x0, double x1, double y0, double y1, double width = 1000,
                  double height = 170);
  /// Grid lines, tick labels and the axis titles, as SVG elements.
  std::string axes(std::string_view x_title, std::string_view y_title) const;
};

/// A min/max band: the polygon through (x_i, hi_i) forward and (x_i, lo_i) backward, in data
/// units mapped through `f`; one sample per column makes it a line.
std::string band(const Frame& f, const std::vector<double>& x, const std::vector<double>& lo,
                 const std::vector<double>& hi, std::string_view colour,
                 std::string_view extra_attrs = "");

}  // namespace gm::report
