// SVG building blocks for the report: linear scales, nice ticks, polylines, min/max bands, axes.
#include "report/svg.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace gm::report {

std::string coord(double v, int decimals) {
  std::string s = fmt::format("{:.{}f}", v, decimals);
  if (s.front() == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}

std::string points_attr(const std::vector<std::pair<double, double>>& pts, int decimals) {
  std::string s;
  s.reserve(pts.size() * 14);
  for (const auto& [x, y] : pts) {
    if (!s.empty()) s += ' ';
    s += coord(x, decimals);
    s += ',';
    s += coord(y, decimals);
  }
  return s;
}

std::vector<double> nice_ticks(double lo, double hi, int n) {
  std::vector<double> t;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi) || n < 1) return t;
  const double raw = (hi - lo) / n;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double r = raw / mag;
  const double step = (r < 1.5 ? 1.0 : r < 3.5 ? 2.0 : r < 7.5 ? 5.0 : 10.0) * mag;
  // Counted, not stepped: a step below the resolution of lo (a narrow range far from 0) would
  // never advance v.
  const double first = std::ceil(lo / step), last = std::floor(hi / step + 1e-9);
  if (!(last >= first) || last - first > 100) return t;
  for (int i = 0; i <= static_cast<int>(last - first); ++i) {
    const double v = (first + i) * step;
    t.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
  }
  return t;
}

std::pair<double, double> padded_range(double lo, double hi) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || lo > hi) return {-1.0, 1.0};
  if (hi == lo) {
    const double d = lo == 0.0 ? 1.0 : std::abs(lo) * 0.1;
    return {lo - d, hi + d};
  }
  const double pad = (hi - lo) * 0.05;
  return {lo - pad, hi + pad};
}

std::string tick_label(double v) {
  return fmt::format("{:.4g}", v);
}

Frame Frame::of(double x0, double x1, double y0, double y1, double width, double height) {
  Frame f;
  f.width = width;
  f.height = height;
  f.x = {x0, x1, f.left, width - f.right};
  f.y = {y0, y1, height - f.bottom, f.top};
  return f;
}

std::string Frame::axes(std::string_view x_title, std::string_view y_title) const {
  std::string s;
  const double px0 = x.p0, px1 = x.p1, py0 = y.p0, py1 = y.p1;
  s += fmt::format(R"(<rect class="plot" x="{}" y="{}" width="{}" height="{}"/>)", coord(px0, 1),
                   coord(py1, 1), coord(px1 - px0, 1), coord(py0 - py1, 1));
  for (const double v : nice_ticks(y.d0, y.d1, 4)) {
    const double py = y(v);
    s += fmt::format(R"(<line class="grid" x1="{}" x2="{}" y1="{}" y2="{}"/>)", coord(px0, 1),
                     coord(px1, 1), coord(py, 1), coord(py, 1));
    s += fmt::format(R"(<text class="tick" x="{}" y="{}" text-anchor="end">{}</text>)",
                     coord(px0 - 4, 1), coord(py + 4, 1), tick_label(v));
  }
  for (const double v : nice_ticks(x.d0, x.d1, 8)) {
    const double px = x(v);
    s += fmt::format(R"(<line class="grid" x1="{}" x2="{}" y1="{}" y2="{}"/>)", coord(px, 1),
                     coord(px, 1), coord(py0, 1), coord(py1, 1));
    s += fmt::format(R"(<text class="tick" x="{}" y="{}" text-anchor="middle">{}</text>)",
                     coord(px, 1), coord(py0 + 14, 1), tick_label(v));
  }
  s += fmt::format(R"(<text class="title" x="{}" y="{}" text-anchor="end">{}</text>)",
                   coord(px1, 1), coord(height - 2, 1), x_title);
  s += fmt::format(R"(<text class="title" x="{}" y="{}">{}</text>)", coord(px0 + 4, 1),
                   coord(py1 + 12, 1), y_title);
  return s;
}

std::string band(const Frame& f, const std::vector<double>& x, const std::vector<double>& lo,
                 const std::vector<double>& hi, std::string_view colour,
                 std::string_view extra_attrs) {
  std::vector<std::pair<double, double>> pts;
  pts.reserve(2 * x.size());
  for (std::size_t i = 0; i < x.size(); ++i) pts.emplace_back(f.x(x[i]), f.y(hi[i]));
  for (std::size_t i = x.size(); i-- > 0;) pts.emplace_back(f.x(x[i]), f.y(lo[i]));
  return fmt::format(R"(<polygon class="band" points="{}" fill="{}" stroke="{}"{}{}/>)",
                     points_attr(pts, 1), colour, colour, extra_attrs.empty() ? "" : " ",
                     extra_attrs);
}

}  // namespace gm::report
