// ToleranceCheck: per-sample comparison of the contour error with the block's tolerance.
#include "measure/tolerance_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace gm {

void ToleranceCheck::add_block(const SampleBlock& b, int first, double period_s) {
  const std::size_t motions = b.motions.size();
  std::size_t m = 0;
  while (m < motions && b.motion_row[m] < first) ++m;
  int i = first;
  while (i < b.count) {
    // The last motion started in row i sets the tolerance up to the next row that starts one.
    while (m < motions && b.motion_row[m] == i) start(b.motions[m++]);
    const int end = m < motions ? std::min(b.motion_row[m], b.count) : b.count;
    if (!(tol_mm_ > 0.0)) {
      i = end;  // nothing judged until the next motion
      continue;
    }
    for (; i < end; ++i)
      judge(b.contour_err_blu[i], b.line[i],
            [&] { return static_cast<double>(b.k0 + i) * period_s; });
  }
}

std::string ToleranceCheck::text() const {
  if (!judged()) return "";
  std::string s;
  for (const auto& [name, w] :
       {std::pair{"cutting (G1/G2/G3)", &cut_}, std::pair{"rapids (G0)", &rapid_}}) {
    if (w->samples == 0) {
      s += fmt::format("  tolerance {}: no sample under a tolerance\n", name);
      continue;
    }
    s += fmt::format(
        "  tolerance {}: worst contour error {:.4f} mm against {:.4f} mm ({:.0f} %) at line {} "
        "(t = {:.3f} s); {} of {} samples over\n",
        name, w->err_mm, w->tol_mm, 100.0 * w->ratio, w->line, w->t_s, w->over, w->samples);
  }
  return s;
}

std::string ToleranceCheck::json_member() const {
  if (!judged()) return "";
  auto worst = [](const Worst& w) {
    if (w.samples == 0) return std::string("{\"samples\":0}");
    return fmt::format(
        "{{\"samples\":{},\"over\":{},\"worst_err_mm\":{:.9g},\"tolerance_mm\":{:.9g},"
        "\"ratio\":{:.9g},\"line\":{},\"t_s\":{:.9g}}}",
        w.samples, w.over, w.err_mm, w.tol_mm, w.ratio, w.line, w.t_s);
  };
  return fmt::format("\"tolerance\":{{\"allowance_mm\":{:.9g},\"cutting\":{},\"rapids\":{}}}",
                     allowance_mm_, worst(cut_), worst(rapid_));
}

}  // namespace gm
