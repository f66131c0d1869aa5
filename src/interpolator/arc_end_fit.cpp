// ArcEndFit: the offsets on a pre-compensated arc's first and last samples, radial and tangential,
// fitted for the least worst distance of the Acc/Dec output from the path, and that distance.
#include "interpolator/arc_end_fit.hpp"

#include "accdec/taps.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

namespace gm {

// A point or direction in the arc's plane (a named type: ArcEndFit::Samples holds it).
struct ArcEndVec {
  double x = 0.0, y = 0.0;
};

namespace {

using EndVec = ArcEndVec;

EndVec operator-(EndVec a, EndVec b) {
  return {a.x - b.x, a.y - b.y};
}
double end_dot(EndVec a, EndVec b) {
  return a.x * b.x + a.y * b.y;
}
double end_norm(EndVec a) {
  return std::hypot(a.x, a.y);
}
EndVec unit_or_zero(EndVec a) {
  const double n = end_norm(a);
  return n > 0.0 ? EndVec{a.x / n, a.y / n} : EndVec{};
}

// The nearer of two (distance, gradient) candidates.
void keep_nearer(std::pair<double, EndVec>& best, double d, EndVec g) {
  if (d < best.first) best = {d, g};
}

}  // namespace

ArcRun ArcRun::constant(double radius_mm, double sweep_rad, double v_mm_s, double period_s,
                        double phase, int window) {
  ArcRun run;
  run.radius_mm = radius_mm;
  run.sweep_rad = sweep_rad;
  const int arc_samples =
      std::isfinite(sweep_rad) ? static_cast<int>(radius_mm * sweep_rad / (v_mm_s * period_s)) : 0;
  run.speed_mm_s.assign(static_cast<std::size_t>(6 * window + arc_samples), v_mm_s);
  run.first = 2 * window;
  run.phase = phase;
  run.planned_mm_s = v_mm_s;
  return run;
}

struct ArcEndFit::Samples {
  std::size_t n = 0;
  double r = 1.0, sweep = 0.0, length = 0.0;
  std::vector<double> s, sbar, c;  // path position, the window's mean position, steady correction
  std::vector<char> on;            // on the arc (a sample resting on its end point is past it)
  std::vector<EndVec> point, normal, tangent;
  double c_planned = 0.0, loss_planned = 0.0;

  // The path's point at path length s.
  EndVec at(double s_mm) const {
    if (s_mm <= 0.0) return {s_mm, 0.0};
    if (s_mm <= length) return {r * std::sin(s_mm / r), r * (1.0 - std::cos(s_mm / r))};
    const EndVec u{std::cos(sweep), std::sin(sweep)};
    const double past = s_mm - length;
    return {r * std::sin(sweep) + past * u.x, r * (1.0 - std::cos(sweep)) + past * u.y};
  }
  // |p − x(s̄)| and its gradient.
  std::pair<double, EndVec> from_mean(EndVec p, double sbar_mm) const {
    const EndVec e = p - at(sbar_mm);
    return {end_norm(e), unit_or_zero(e)};
  }
  // Distance of p from the path and its gradient; sbar decides, on an endless arc, whether the
  // circle is already in play where p is still left of the start.
  std::pair<double, EndVec> distance(EndVec p, double sbar_mm) const {
    std::pair<double, EndVec> best{std::abs(p.y), EndVec{0.0, p.y < 0.0 ? -1.0 : 1.0}};
    if (p.x > 0.0) best = {end_norm(p), unit_or_zero(p)};  // the start point
    const EndVec centre{0.0, r};
    const double rho = end_norm(p - centre);
    const EndVec out = unit_or_zero(p - centre);
    const double sign = rho >= r ? 1.0 : -1.0;
    if (!std::isfinite(sweep)) {
      if (p.x >= 0.0 || sbar_mm > r * 0.5 * std::numbers::pi)
        keep_nearer(best, std::abs(rho - r), EndVec{sign * out.x, sign * out.y});
      return best;
    }
    const EndVec end{r * std::sin(sweep), r * (1.0 - std::cos(sweep))};
    const double turn =
        std::fmod(std::atan2(p.y - r, p.x) + 0.5 * std::numbers::pi + 2.0 * std::numbers::pi,
                  2.0 * std::numbers::pi);
    if (turn <= sweep)
      keep_nearer(best, std::abs(rho - r), EndVec{sign * out.x, sign * out.y});
    else
      keep_nearer(best, end_norm(p - end), unit_or_zero(p - end));
    const EndVec u{std::cos(sweep), std::sin(sweep)}, across{-u.y, u.x};
    const double along = end_dot(p - end, u), side = end_dot(p - end, across);
    if (along >= 0.0)
      keep_nearer(best, std::abs(side),
                  EndVec{side < 0.0 ? -across.x : across.x, side < 0.0 ? -across.y : across.y});
    else
      keep_nearer(best, end_norm(p - end), unit_or_zero(p - end));
    return best;
  }
};

ArcEndFit::ArcEndFit(std::vector<double> weights, double period_s)
    : h_(std::move(weights)), period_s_(period_s) {
  for (std::size_t i = 0; i < h_.size(); ++i) centre_ += static_cast<double>(i) * h_[i];
  symmetric_ = weights_symmetric(h_);
}

double ArcEndFit::gain(double x) const {
  return weights_gain(h_, centre_, symmetric_, x);
}

ArcEndFit::Samples ArcEndFit::prepare(const ArcRun& run, bool means) const {
  Samples sm;
  sm.n = run.speed_mm_s.size();
  sm.r = run.radius_mm;
  sm.sweep = run.sweep_rad;
  sm.length = std::isfinite(run.sweep_rad) ? run.radius_mm * run.sweep_rad
                                           : std::numeric_limits<double>::infinity();
  const std::size_t n = sm.n;
  const auto first = static_cast<std::size_t>(run.first);
  sm.s.resize(n);
  double acc = 0.0;
  for (std::size_t i = 0; i < n; ++i) sm.s[i] = acc += run.speed_mm_s[i] * period_s_;
  const double shift = sm.s[first] - run.phase * run.speed_mm_s[first] * period_s_;
  for (double& v : sm.s) v -= shift;
  sm.c.assign(n, 0.0);
  sm.on.assign(n, 0);
  sm.point.resize(n);
  sm.normal.assign(n, {});
  sm.tangent.resize(n);
  const double r = sm.r;
  double last_x = std::numeric_limits<double>::quiet_NaN(), last_c = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double s = sm.s[i];
    if (s <= 0.0) {
      sm.point[i] = {s, 0.0};
      sm.tangent[i] = {1.0, 0.0};
    } else if (s <= sm.length) {
      const double a = s / r;
      sm.point[i] = {r * std::sin(a), r * (1.0 - std::cos(a))};
      sm.normal[i] = {std::sin(a), -std::cos(a)};
      sm.tangent[i] = {std::cos(a), std::sin(a)};
    } else {
      const EndVec u{std::cos(sm.sweep), std::sin(sm.sweep)};
      const double past = s - sm.length;
      sm.point[i] = {r * std::sin(sm.sweep) + past * u.x,
                     r * (1.0 - std::cos(sm.sweep)) + past * u.y};
      sm.tangent[i] = u;
    }
    if (s > 0.0 && s < sm.length - 1e-9 * r) {
      sm.on[i] = 1;
      const double x = run.speed_mm_s[i] * period_s_ / r;
      if (x != last_x) {  // a run's speeds repeat: A(x) once per speed
        last_x = x;
        last_c = r * (1.0 / gain(x) - 1.0);
      }
      sm.c[i] = last_c;
    }
  }
  const double x_planned = run.planned_mm_s * period_s_ / r;
  sm.c_planned = r * (1.0 / gain(x_planned) - 1.0);
  sm.loss_planned = r * (1.0 - gain(x_planned));
  sm.sbar.assign(n, 0.0);
  if (!means) return sm;
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t i = 0; i < h_.size() && i <= k; ++i) sm.sbar[k] += h_[i] * sm.s[k - i];
  return sm;
}

ArcOffsets ArcEndFit::linear_blend(const ArcRun& run) const {
  const Samples sm = prepare(run);
  const double blend = std::min(0.5 * sm.length, 2.0 * period_s_ * run.planned_mm_s);
  ArcOffsets off{std::vector<double>(sm.n, 0.0), std::vector<double>(sm.n, 0.0)};
  for (std::size_t i = 0; i < sm.n; ++i)
    if (sm.on[i] != 0) {
      const double d = std::min(sm.s[i], sm.length - sm.s[i]);
      off.radial_mm[i] = std::min(1.0, d / blend) * sm.c[i];
    }
  return off;
}

std::vector<ArcSample> ArcEndFit::samples(const ArcRun& run) const {
  const Samples sm = prepare(run, false);
  std::vector<ArcSample> out(sm.n);
  for (std::size_t i = 0; i < sm.n; ++i) {
    const double adv = run.speed_mm_s[i] * period_s_;
    out[i] = {sm.on[i] != 0, sm.s[i], adv, sm.c[i], adv / sm.r};
  }
  return out;
}

namespace {

// x^p for p a power of two (p >= 1), by squaring.
double power_of_two(double x, int p) {
  for (; p > 1; p /= 2) x *= x;
  return x;
}

}  // namespace

std::vector<double> ArcEndFit::fit_shared(const std::vector<ArcRun>& runs,
                                          const std::vector<ArcCommandModel>& models, double mu,
                                          ArcEndMeasure measure) const {
  // At most kMaxUnknowns unknowns: the solver's vectors and matrices on the stack. The rows'
  // sums are plain loops over flat arrays (they are most of the work).
  using Vec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxUnknowns, 1>;
  using Mat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxUnknowns, kMaxUnknowns>;
  const std::size_t m = h_.size();
  const std::size_t f = models.empty() ? 0 : models.front().columns.size();
  // Every sample whose window is full, of every run: the residual r = y − x(s̄) of the base
  // command (rx, ry) and its derivative by the unknowns (jx, jy: f each; the filter is linear in
  // them). Rows the unknowns do not reach keep only their constant |r| (`fixed`).
  std::vector<double> rx, ry, jx, jy, fixed;
  // By the distance: each reached row's base output (absolute), its window's mean and its run
  // (the distance is linearised again around each pass's unknowns).
  const bool by_distance = measure == ArcEndMeasure::Distance;
  std::vector<Samples> prepared;
  std::vector<double> yb_x, yb_y, row_sbar;
  std::vector<std::size_t> row_run;
  double c_unit = 0.0;
  std::vector<double> bx, by, cx, cy;
  std::vector<std::size_t> col_first(f), col_last(f);
  for (std::size_t r = 0; r < runs.size(); ++r) {
    prepared.push_back(prepare(runs[r]));
    const Samples& sm = prepared.back();
    if (r == 0) c_unit = sm.c_planned;
    // An offset's command at sample i: radial along the normal, along the motion.
    const auto offset = [&sm](const ArcOffsets& off, std::size_t i, double& x, double& y) {
      x = off.radial_mm[i] * sm.normal[i].x + off.along_mm[i] * sm.tangent[i].x;
      y = off.radial_mm[i] * sm.normal[i].y + off.along_mm[i] * sm.tangent[i].y;
    };
    // The base command and each column's on every sample, once; a column's non-zero span.
    bx.assign(sm.n, 0.0);
    by.assign(sm.n, 0.0);
    cx.assign(sm.n * f, 0.0);
    cy.assign(sm.n * f, 0.0);
    for (std::size_t i = 0; i < sm.n; ++i) {
      offset(models[r].base, i, bx[i], by[i]);
      bx[i] += sm.point[i].x;
      by[i] += sm.point[i].y;
    }
    for (std::size_t q = 0; q < f; ++q) {
      col_first[q] = sm.n;
      col_last[q] = 0;
      for (std::size_t i = 0; i < sm.n; ++i) {
        double x, y;
        offset(models[r].columns[q], i, x, y);
        if (x == 0.0 && y == 0.0) continue;
        cx[q * sm.n + i] = x;
        cy[q * sm.n + i] = y;
        col_first[q] = std::min(col_first[q], i);
        col_last[q] = i;
      }
    }
    for (std::size_t k = m - 1; k < sm.n; ++k) {
      double yx = 0.0, yy = 0.0;
      for (std::size_t i = 0; i < m; ++i) {
        yx += h_[i] * bx[k - i];
        yy += h_[i] * by[k - i];
      }
      bool reached = false;
      for (std::size_t q = 0; q < f && !reached; ++q)
        reached = col_first[q] <= col_last[q] && col_first[q] <= k && col_last[q] + m > k;
      if (!reached) {
        fixed.push_back(by_distance ? sm.distance({yx, yy}, sm.sbar[k]).first
                                    : sm.from_mean({yx, yy}, sm.sbar[k]).first);
        continue;
      }
      if (by_distance) {
        yb_x.push_back(yx);
        yb_y.push_back(yy);
        row_sbar.push_back(sm.sbar[k]);
        row_run.push_back(r);
      }
      const EndVec at = sm.at(sm.sbar[k]);
      yx -= at.x;
      yy -= at.y;
      rx.push_back(yx);
      ry.push_back(yy);
      for (std::size_t q = 0; q < f; ++q) {
        double dx = 0.0, dy = 0.0;
        const std::size_t lo = k + 1 >= m ? k + 1 - m : 0;
        for (std::size_t i = std::max(lo, col_first[q]); i <= std::min(k, col_last[q]); ++i) {
          dx += h_[k - i] * cx[q * sm.n + i];
          dy += h_[k - i] * cy[q * sm.n + i];
        }
        jx.push_back(dx);
        jy.push_back(dy);
      }
    }
  }
  const std::size_t rows = rx.size();
  const std::vector<double> jx_abs = by_distance ? jx : std::vector<double>{},
                            jy_abs = by_distance ? jy : std::vector<double>{};
  const double n = static_cast<double>(rows + fixed.size()), reg = mu * c_unit * c_unit;
  const double fixed_top = fixed.empty() ? 0.0 : *std::max_element(fixed.begin(), fixed.end());
  // The rows the unknowns do not reach enter every power mean as one sum: Σ (d/t0)^p =
  // (fixed_top/t0)^p · Σ (d/fixed_top)^p, the second factor once per p (p = 2^j, j < 8). They
  // are most of the rows (an endless run's steady part), so most of the power means' cost.
  std::array<double, 8> fixed_scaled{};
  if (fixed_top > 0.0)
    for (std::size_t j = 1; j < fixed_scaled.size(); ++j)
      for (double d : fixed) fixed_scaled[j] += power_of_two(d / fixed_top, 1 << j);
  const auto fixed_sum = [&](int p, double t0) {
    if (!(fixed_top > 0.0)) return 0.0;
    return fixed_scaled[static_cast<std::size_t>(std::countr_zero(static_cast<unsigned>(p)))] *
           power_of_two(fixed_top / t0, p);
  };
  Vec u = Vec::Zero(static_cast<Eigen::Index>(f));
  std::vector<double> dist(rows), ex(rows), ey(rows);
  // At u: the residuals, their lengths, the largest t0 and S = mean((|r_k| / t0)^p).
  const auto evaluate = [&](const Vec& v, int p, double& t0, double& s) {
    t0 = fixed_top;
    const double* vq = v.data();
    for (std::size_t k = 0; k < rows; ++k) {
      double x = rx[k], y = ry[k];
      const double* ax = &jx[k * f];
      const double* ay = &jy[k * f];
      for (std::size_t q = 0; q < f; ++q) {
        x += ax[q] * vq[q];
        y += ay[q] * vq[q];
      }
      ex[k] = x;
      ey[k] = y;
      dist[k] = std::sqrt(x * x + y * y);
      t0 = std::max(t0, dist[k]);
    }
    s = 0.0;
    if (!(t0 > 0.0)) return;
    for (double d : dist) s += power_of_two(d / t0, p);
    s += fixed_sum(p, t0);
    s /= n;
  };
  // J(u) = M_p² + reg·|u|², M_p = t0·S^(1/p).
  const auto objective = [&](const Vec& v, int p) {
    double t0, s;
    evaluate(v, p, t0, s);
    const double mp = t0 * std::pow(s, 1.0 / p);
    return mp * mp + reg * v.squaredNorm();
  };
  double jr[kMaxUnknowns], grad_sum[kMaxUnknowns], hess_sum[kMaxUnknowns * kMaxUnknowns];
  // Minimises the power mean of |r + J·u| from p_first on, from the present u.
  const auto solve = [&](int p_first) {
    for (int p = p_first; p <= 128 && f > 0; p *= 2) {
      for (int it = 0; it < 30; ++it) {
        double t0, s;
        evaluate(u, p, t0, s);
        if (!(t0 > 0.0)) break;
        const double mp = t0 * std::pow(s, 1.0 / p), j0 = mp * mp + reg * u.squaredNorm();
        // M_p² = G^(2/p), G = mean |r_k|^p: ∇ = 2·S^(2/p − 1)·mean(ρ^(p−2)·Jᵀr) = g and
        // ∇² = H − (p/2 − 1)/M_p²·g·gᵀ, H = 2·S^(2/p − 1)·mean(ρ^(p−2)·Jᵀ(I + (p − 2)·r̂r̂ᵀ)J):
        // Newton on the whole, or on H alone where the whole is not positive definite.
        const double scale = 2.0 * std::pow(s, 2.0 / p - 1.0) / n;
        const auto nf = static_cast<Eigen::Index>(f);
        // The sums in plain arrays (hess_sum: the lower triangle, row a at a·f), then Eigen's.
        for (std::size_t a = 0; a < f; ++a) {
          grad_sum[a] = 2.0 * reg * u[static_cast<Eigen::Index>(a)];
          for (std::size_t b = 0; b <= a; ++b) hess_sum[a * f + b] = a == b ? 2.0 * reg : 0.0;
        }
        for (std::size_t k = 0; k < rows; ++k) {
          if (!(dist[k] > 0.0)) continue;
          // A row whose ρ^p is below 10⁻²⁰ of the worst's (ρ = 1) is below the sums' rounding.
          const double rho = dist[k] / t0, rho_p = power_of_two(rho, p);
          if (rho_p < 1e-20) continue;
          const double w = scale * rho_p / (rho * rho);
          const double* ax = &jx[k * f];
          const double* ay = &jy[k * f];
          for (std::size_t q = 0; q < f; ++q) jr[q] = ax[q] * ex[k] + ay[q] * ey[k];
          const double w2 = w * (p - 2.0) / (dist[k] * dist[k]);
          for (std::size_t a = 0; a < f; ++a) {
            grad_sum[a] += w * jr[a];
            for (std::size_t b = 0; b <= a; ++b)
              hess_sum[a * f + b] += w * (ax[a] * ax[b] + ay[a] * ay[b]) + w2 * jr[a] * jr[b];
          }
        }
        Vec grad(nf);
        Mat hess(nf, nf);
        for (std::size_t a = 0; a < f; ++a) {
          grad[static_cast<Eigen::Index>(a)] = grad_sum[a];
          for (std::size_t b = 0; b <= a; ++b)
            hess(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) = hess_sum[a * f + b];
        }
        hess.template triangularView<Eigen::StrictlyUpper>() = hess.transpose();
        const Vec g_mp = grad - 2.0 * reg * u;
        const Eigen::LLT<Mat> whole(
            Mat(hess - (0.5 * p - 1.0) / (mp * mp) * g_mp * g_mp.transpose()));
        const Vec step = whole.info() == Eigen::Success ? Vec(-whole.solve(grad))
                                                        : Vec(-hess.ldlt().solve(grad));
        double a = 1.0;
        bool better = false;
        for (; a > 1e-6; a *= 0.5)
          if (objective(u + a * step, p) <= j0) {
            better = true;
            break;
          }
        if (!better) break;
        u += a * step;
        if ((a * step).norm() <= 1e-9 * (1.0 + u.norm())) break;
      }
    }
  };
  if (!by_distance || f == 0) {
    solve(2);
    return {u.data(), u.data() + u.size()};
  }
  // By the distance d: around the present u it is d(u') ≈ d(u) + g·J·(u' − u) (g its gradient
  // at the output), a residual along g, whose power mean is minimised as above; then again
  // around the result. The unknowns with the least worst true distance are kept.
  const auto output = [&](const Vec& v, std::size_t k) {
    EndVec y{yb_x[k], yb_y[k]};
    const double* vq = v.data();
    for (std::size_t q = 0; q < f; ++q) {
      y.x += jx_abs[k * f + q] * vq[q];
      y.y += jy_abs[k * f + q] * vq[q];
    }
    return y;
  };
  const auto worst_distance = [&](const Vec& v) {
    double worst = fixed_top;
    for (std::size_t k = 0; k < rows; ++k)
      worst = std::max(worst, prepared[row_run[k]].distance(output(v, k), row_sbar[k]).first);
    return worst;
  };
  Vec best = u;
  double best_worst = worst_distance(u);
  for (int pass = 0; pass < kDistancePasses; ++pass) {
    const double* uq = u.data();
    for (std::size_t k = 0; k < rows; ++k) {
      const auto [d, g] = prepared[row_run[k]].distance(output(u, k), row_sbar[k]);
      double gju = 0.0;
      for (std::size_t q = 0; q < f; ++q) {
        const double gj = g.x * jx_abs[k * f + q] + g.y * jy_abs[k * f + q];
        jx[k * f + q] = g.x * gj;
        jy[k * f + q] = g.y * gj;
        gju += gj * uq[q];
      }
      rx[k] = g.x * (d - gju);
      ry[k] = g.y * (d - gju);
    }
    solve(pass == 0 ? 2 : 32);
    const double w = worst_distance(u);
    if (w < best_worst) best_worst = w, best = u;
  }
  return {best.data(), best.data() + best.size()};
}

double ArcEndFit::worst_fraction(const ArcRun& run, const ArcOffsets& off,
                                 ArcEndMeasure measure) const {
  const Samples sm = prepare(run);
  const std::size_t n = sm.n, m = h_.size();
  std::vector<EndVec> cmd(sm.point);
  for (std::size_t i = 0; i < n; ++i) {
    cmd[i].x += off.radial_mm[i] * sm.normal[i].x + off.along_mm[i] * sm.tangent[i].x;
    cmd[i].y += off.radial_mm[i] * sm.normal[i].y + off.along_mm[i] * sm.tangent[i].y;
  }
  double worst = 0.0;
  for (std::size_t k = m - 1; k < n; ++k) {
    EndVec y;
    for (std::size_t i = 0; i < m; ++i) {
      y.x += h_[i] * cmd[k - i].x;
      y.y += h_[i] * cmd[k - i].y;
    }
    worst = std::max(worst, (measure == ArcEndMeasure::Distance ? sm.distance(y, sm.sbar[k])
                                                                : sm.from_mean(y, sm.sbar[k]))
                                .first);
  }
  return worst / sm.loss_planned;
}

}  // namespace gm
