// Renders a divergence: the traces are read whole (goldens are decimated and small) and drawn.
#include "golden/divergence_plot.hpp"

#include "golden/png_writer.hpp"
#include "trace/trace_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>

namespace gm::golden {
namespace {

using Table = std::vector<std::vector<double>>;  // rows of values

Table read_all(const std::string& path, std::vector<std::string>& columns) {
  TraceReader t(path);
  columns = t.columns();
  Table rows;
  std::vector<double> v;
  while (t.next(v)) rows.push_back(v);
  return rows;
}

constexpr Rgb kGolden{40, 90, 200}, kNow{210, 40, 40}, kInk{0, 0, 0}, kGrid{200, 200, 200};

// A plot frame: data ranges mapped into a pixel box.
struct Frame {
  int x0, y0, x1, y1;  // pixels, y0 top
  double u0, u1, v0, v1;
  double px(double u) const { return x0 + (u - u0) / (u1 - u0) * (x1 - x0); }
  double py(double v) const { return y1 - (v - v0) / (v1 - v0) * (y1 - y0); }
};

void widen(double& lo, double& hi) {
  if (!(hi > lo)) lo -= 1.0, hi += 1.0;
  const double pad = (hi - lo) * 0.05;
  lo -= pad, hi += pad;
}

}  // namespace

std::string draw_divergence(const std::string& golden_trace, const std::string& fresh_trace,
                            const Divergence& d, const std::string& title,
                            const std::filesystem::path& png) {
  try {
    std::vector<std::string> cols, cols_f;
    const Table g = read_all(golden_trace, cols), f = read_all(fresh_trace, cols_f);
    if (cols != cols_f || g.empty() || f.empty())
      return "the traces have different columns or no rows";
    const auto col = std::find(cols.begin(), cols.end(), d.column);
    if (col == cols.end()) return "no column " + d.column;
    const std::size_t dc = static_cast<std::size_t>(col - cols.begin());
    const std::size_t at = static_cast<std::size_t>(std::max<std::int64_t>(d.row - 1, 0));

    // The path plane: two axis columns of the diverging column's kind (else the encoders).
    std::string kind = "enc";
    if (d.column.size() > 2 && d.column[1] == '_') {
      const std::string k = d.column.substr(2);
      if (k == "cmd" || k == "ref" || k == "enc") kind = k;
    }
    const std::size_t n = std::min(g.size(), f.size());
    const std::size_t w = std::max<std::size_t>(50, n / 10);
    const std::size_t lo = at > w ? at - w : 0, hi = std::min(n, at + w + 1);
    std::vector<std::size_t> axes;
    for (std::size_t i = 0; i < cols.size(); ++i)
      if (cols[i].size() > 2 && cols[i][1] == '_' && cols[i].substr(2) == kind) axes.push_back(i);
    auto range = [&](std::size_t c) {
      double a = std::numeric_limits<double>::infinity(), b = -a;
      for (std::size_t r = lo; r < hi; ++r)
        a = std::min({a, g[r][c], f[r][c]}), b = std::max({b, g[r][c], f[r][c]});
      return b - a;
    };
    // The two axes that move most around the divergence, in trace order.
    std::sort(axes.begin(), axes.end(),
              [&](std::size_t a, std::size_t b) { return range(a) > range(b); });
    if (axes.size() > 2) axes.resize(2);
    std::sort(axes.begin(), axes.end());

    Raster img(1000, 900);
    img.text(20, 12,
             fmt::format("{}: first divergence t = {:.4f} s, line {}, {}", title, d.t_s, d.line,
                         d.column),
             kInk, 2);
    img.text(20, 36, fmt::format("golden {}  now {}", d.golden, d.fresh), kInk, 2);
    img.text(700, 36, "golden", kGolden, 2);
    img.text(800, 36, "now", kNow, 2);

    if (axes.size() == 2) {
      const std::size_t cx = axes[0], cy = axes[1];
      double u0 = std::numeric_limits<double>::infinity(), u1 = -u0, v0 = u0, v1 = -u0;
      for (std::size_t r = lo; r < hi; ++r)
        for (const Table* t : {&g, &f}) {
          u0 = std::min(u0, (*t)[r][cx]), u1 = std::max(u1, (*t)[r][cx]);
          v0 = std::min(v0, (*t)[r][cy]), v1 = std::max(v1, (*t)[r][cy]);
        }
      widen(u0, u1), widen(v0, v1);
      // Equal scales on both axes, centred in a 560 x 500 box.
      const double span = std::max(u1 - u0, (v1 - v0) * 560.0 / 500.0);
      const double uc = (u0 + u1) / 2, vc = (v0 + v1) / 2, vspan = span * 500.0 / 560.0;
      const Frame fr{220,           70, 780, 570, uc - span / 2, uc + span / 2, vc - vspan / 2,
                     vc + vspan / 2};
      img.rect(fr.x0, fr.y0, fr.x1, fr.y1, kGrid);
      // The golden 3 px wide under the 1 px run, so both show where they coincide.
      auto seg = [&](const Table& t, std::size_t r, double off, Rgb c) {
        img.line(fr.px(t[r - 1][cx]) + off, fr.py(t[r - 1][cy]) + off, fr.px(t[r][cx]) + off,
                 fr.py(t[r][cy]) + off, c);
      };
      for (std::size_t r = lo + 1; r < hi; ++r)
        for (double off : {-1.0, 0.0, 1.0}) seg(g, r, off, kGolden);
      for (std::size_t r = lo + 1; r < hi; ++r) seg(f, r, 0.0, kNow);
      const double mx = fr.px(f[at][cx]), my = fr.py(f[at][cy]);
      img.line(mx - 8, my - 8, mx + 8, my + 8, kInk);
      img.line(mx - 8, my + 8, mx + 8, my - 8, kInk);
      img.text(fr.x0, fr.y1 + 6, fmt::format("{} {:.0f} .. {:.0f} BLU", cols[cx], fr.u0, fr.u1),
               kInk);
      img.text(fr.x0 - 200, fr.y0, fmt::format("{} {:.0f}", cols[cy], fr.v1), kInk);
      img.text(fr.x0 - 200, fr.y1 - 7, fmt::format("{} {:.0f}", cols[cy], fr.v0), kInk);
      img.text(fr.x1 + 10, fr.y0, fmt::format("rows {}..{}", lo + 1, hi), kInk);
    }

    // The difference now - golden of the diverging column against time, every row.
    double t0 = g.front()[0], t1 = g[n - 1][0], e0 = 0.0, e1 = 0.0;
    for (std::size_t r = 0; r < n; ++r)
      e0 = std::min(e0, f[r][dc] - g[r][dc]), e1 = std::max(e1, f[r][dc] - g[r][dc]);
    widen(t0, t1), widen(e0, e1);
    const Frame fd{120, 640, 960, 860, t0, t1, e0, e1};
    img.rect(fd.x0, fd.y0, fd.x1, fd.y1, kGrid);
    img.line(fd.x0, fd.py(0.0), fd.x1, fd.py(0.0), kGrid);
    img.line(fd.px(d.t_s), fd.y0, fd.px(d.t_s), fd.y1, kInk);
    for (std::size_t r = 1; r < n; ++r)
      img.line(fd.px(g[r - 1][0]), fd.py(f[r - 1][dc] - g[r - 1][dc]), fd.px(g[r][0]),
               fd.py(f[r][dc] - g[r][dc]), kNow);
    img.text(fd.x0, fd.y0 - 14, fmt::format("{}: now - golden against time", d.column), kInk, 1);
    img.text(10, fd.y0, fmt::format("{:+.4g}", e1), kInk);
    img.text(10, fd.y1 - 7, fmt::format("{:+.4g}", e0), kInk);
    img.text(fd.x0, fd.y1 + 6, fmt::format("t {:.3f} s", t0), kInk);
    img.text(fd.x1 - 80, fd.y1 + 6, fmt::format("{:.3f} s", t1), kInk);
    return write_png(img, png.string());
  } catch (const std::exception& e) {
    return e.what();
  }
}

}  // namespace gm::golden
