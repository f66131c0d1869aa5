// ToleranceCheck: per-sample comparison of the contour error with the block's tolerance.
#include "planner/tolerance_check.hpp"

#include <fmt/format.h>

#include <cmath>

namespace gm {

void ToleranceCheck::add(const SampleRecord& r, const Motion* started) {
  if (started != nullptr) {
    tol_mm_ = started->path_mode == PathMode::Continuous ? started->path_tolerance_mm : 0.0;
    rapid_block_ = started->kind == MotionKind::Rapid;
  }
  if (!(tol_mm_ > 0.0)) return;
  Worst& w = rapid_block_ ? rapid_ : cut_;
  const double err = std::abs(r.contour_err_blu) * blu_mm_;
  ++w.samples;
  // A nanometre of slack for the BLU-to-mm products (the bound itself is planned with margin).
  if (err > tol_mm_ + allowance_mm_ + 1e-9) ++w.over;
  const double ratio = err / tol_mm_;
  if (ratio > w.ratio) {
    w.ratio = ratio;
    w.err_mm = err;
    w.tol_mm = tol_mm_;
    w.line = r.line;
    w.t_s = r.t_s;
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
