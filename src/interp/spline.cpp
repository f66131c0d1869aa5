// NURBS points by de Boor's algorithm in homogeneous coordinates, exact tangents from the
// derivative curve, and the equal-tangent biarc between consecutive samples.
#include "interp/spline.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace gm {

namespace {

// LinuxCNC's knot t_i (i = 0 .. n + k) for n + 1 points of order k.
double knot(int i, int n, int k) {
  if (i < k) return 0.0;
  if (i <= n) return static_cast<double>(i - k + 1);
  return static_cast<double>(n - k + 2);
}

// The span s with t_s <= u < t_{s+1} (the last non-empty one at the end).
int span_of(double u, int n, int k) {
  const double umax = n - k + 2;
  if (u >= umax) return n;
  const int s = k - 1 + static_cast<int>(std::floor(std::max(u, 0.0)));
  return std::min(s, n);
}

using H = std::array<double, 3>;  // (w x, w y, w)

// de Boor: the B-spline of order `k` with control vectors c[0..k-1] for span s (c[j] belongs
// to point s - k + 1 + j), knots given by `t(i)`.
template <typename Knot>
H de_boor(std::array<H, 32>& c, int k, int s, double u, const Knot& t) {
  for (int r = 1; r < k; ++r)
    for (int j = k - 1; j >= r; --j) {
      const int i = s - k + 1 + j;
      const double den = t(i + k - r) - t(i);
      const double a = den > 0.0 ? (u - t(i)) / den : 0.0;
      for (int d = 0; d < 3; ++d) c[j][d] = (1.0 - a) * c[j - 1][d] + a * c[j][d];
    }
  return c[k - 1];
}

}  // namespace

CurvePoint nurbs_at(std::span<const ControlPoint> pts, int k, double u) {
  const int n = static_cast<int>(pts.size()) - 1;
  const int s = span_of(u, n, k);
  auto t = [n, k](int i) { return knot(i, n, k); };
  std::array<H, 32> c{};
  for (int j = 0; j < k; ++j) {
    const ControlPoint& p = pts[static_cast<std::size_t>(s - k + 1 + j)];
    c[j] = {p.w * p.x, p.w * p.y, p.w};
  }
  const H a = de_boor(c, k, s, u, t);
  // The derivative is a spline of order k - 1 over the knots t_1 .. t_{n+k-1} with control
  // vectors (k - 1)(P_{i+1} - P_i) / (t_{i+k} - t_{i+1}).
  H da{0.0, 0.0, 0.0};
  if (k > 1) {
    for (int j = 0; j < k - 1; ++j) {
      const int i = s - k + 1 + j;
      const ControlPoint& p0 = pts[static_cast<std::size_t>(i)];
      const ControlPoint& p1 = pts[static_cast<std::size_t>(i + 1)];
      const double den = t(i + k) - t(i + 1);
      const double f = den > 0.0 ? (k - 1) / den : 0.0;
      c[j] = {f * (p1.w * p1.x - p0.w * p0.x), f * (p1.w * p1.y - p0.w * p0.y), f * (p1.w - p0.w)};
    }
    auto t1 = [n, k](int i) { return knot(i + 1, n, k); };
    da = de_boor(c, k - 1, s - 1, u, t1);
  }
  CurvePoint out;
  out.x = a[0] / a[2];
  out.y = a[1] / a[2];
  // P' = (A' - P W') / W; only its direction is kept.
  double tx = (da[0] - out.x * da[2]) / a[2], ty = (da[1] - out.y * da[2]) / a[2];
  const double h = std::hypot(tx, ty);
  if (h > 0.0) {
    tx /= h;
    ty /= h;
  }
  out.tx = tx;
  out.ty = ty;
  return out;
}

namespace {

// The arc from (x0, y0) leaving along unit (dx, dy) to (x1, y1), or a line if it is straight.
CurvePiece arc_piece(double x0, double y0, double dx, double dy, double x1, double y1,
                     double straight_tol) {
  CurvePiece p;
  p.x = x1;
  p.y = y1;
  const double vx = x1 - x0, vy = y1 - y0;
  const double cross = vy * dx - vx * dy;  // chord x tangent: the centre lies on the normal
  if (std::fabs(2.0 * cross) <= straight_tol) return p;
  const double rho = (vx * vx + vy * vy) / (2.0 * cross);  // > 0: centre on the left
  p.arc = true;
  p.cx = x0 - dy * rho;
  p.cy = y0 + dx * rho;
  p.ccw = rho > 0.0;
  return p;
}

void biarc(const CurvePoint& a, const CurvePoint& b, double straight_tol,
           std::vector<CurvePiece>& out) {
  // Equal tangent lengths d: |(P4 - d T4) - (P0 + d T0)| = 2d with v = P4 - P0, i.e.
  // qa d^2 - 2 (v.(T0 + T4)) d + |v|^2 = 0 with qa = 2 (T0.T4 - 1) <= 0: one root d > 0.
  const double vx = b.x - a.x, vy = b.y - a.y;
  const double c = vx * vx + vy * vy;
  if (c == 0.0) return;
  const double vt = vx * (a.tx + b.tx) + vy * (a.ty + b.ty);
  const double qa = 2.0 * (a.tx * b.tx + a.ty * b.ty - 1.0);
  double d = 0.0;
  if (std::fabs(qa) > 1e-12) {
    const double disc = vt * vt - qa * c;  // the discriminant over 4
    d = (vt - std::sqrt(std::max(disc, 0.0))) / qa;
  } else if (vt > 0.0) {
    d = c / (2.0 * vt);  // parallel tangents: the linear equation
  }
  if (!(d > 0.0) || !std::isfinite(d)) {  // no biarc: the chord
    out.push_back(CurvePiece{b.x, b.y});
    return;
  }
  const double p1x = a.x + d * a.tx, p1y = a.y + d * a.ty;
  const double p3x = b.x - d * b.tx, p3y = b.y - d * b.ty;
  const double mx = 0.5 * (p1x + p3x), my = 0.5 * (p1y + p3y);
  double tmx = p3x - p1x, tmy = p3y - p1y;
  const double h = std::hypot(tmx, tmy);
  if (h > 0.0) {
    tmx /= h;
    tmy /= h;
  }
  out.push_back(arc_piece(a.x, a.y, a.tx, a.ty, mx, my, straight_tol));
  out.push_back(arc_piece(mx, my, tmx, tmy, b.x, b.y, straight_tol));
}

}  // namespace

void nurbs_biarcs(std::span<const ControlPoint> pts, int k, double straight_tol,
                  std::vector<CurvePiece>& out) {
  const int n = static_cast<int>(pts.size()) - 1;
  const double umax = n - k + 2;
  const int steps = 4 * static_cast<int>(pts.size());
  CurvePoint a = nurbs_at(pts, k, 0.0);
  for (int i = 1; i <= steps; ++i) {
    const CurvePoint b = nurbs_at(pts, k, umax * i / steps);
    biarc(a, b, straight_tol, out);
    a = b;
  }
}

}  // namespace gm
