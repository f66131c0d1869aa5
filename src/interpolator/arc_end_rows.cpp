// ArcEndFit: the offsets on a pre-compensated arc's first and last samples, radial and tangential,
// fitted for the least worst distance of the Acc/Dec output from the path, and that distance.
#include "interpolator/arc_end_rows.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

namespace gm {

namespace {

struct EndVec {
  double x = 0.0, y = 0.0;
};

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
  std::vector<int> from_start, to_end;  // samples since the arc's first, before its last
  double c_planned = 0.0, loss_planned = 0.0;

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

ArcEndFit::ArcEndFit(std::vector<double> weights, double period_s, double lambda, int iterations)
    : h_(std::move(weights)), period_s_(period_s), lambda_(lambda), iterations_(iterations) {
  for (std::size_t i = 0; i < h_.size(); ++i) centre_ += static_cast<double>(i) * h_[i];
}

double ArcEndFit::gain(double x) const {
  double a = 0.0;
  for (std::size_t i = 0; i < h_.size(); ++i)
    a += h_[i] * std::cos((static_cast<double>(i) - centre_) * x);
  return a;
}

ArcEndFit::Samples ArcEndFit::prepare(const ArcRun& run) const {
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
  int first_on = -1, last_on = -1;
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
      sm.c[i] = r * (1.0 / gain(x) - 1.0);
      if (first_on < 0) first_on = static_cast<int>(i);
      last_on = static_cast<int>(i);
    }
  }
  sm.from_start.assign(n, 1 << 30);
  sm.to_end.assign(n, 1 << 30);
  for (std::size_t i = 0; i < n; ++i)
    if (sm.on[i] != 0) {
      sm.from_start[i] = static_cast<int>(i) - first_on;
      sm.to_end[i] = last_on - static_cast<int>(i);
    }
  const double x_planned = run.planned_mm_s * period_s_ / r;
  sm.c_planned = r * (1.0 / gain(x_planned) - 1.0);
  sm.loss_planned = r * (1.0 - gain(x_planned));
  sm.sbar.assign(n, 0.0);
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

ArcOffsets ArcEndFit::fit(const ArcRun& run) const {
  const Samples sm = prepare(run);
  const std::size_t n = sm.n, m = h_.size();
  // Unknown q: sample sample_of[q], radial (q even) or along the motion (q odd), in units of c.
  std::vector<std::size_t> sample_of;
  std::vector<EndVec> dir;
  std::vector<EndVec> base(sm.point);
  for (std::size_t i = 0; i < n; ++i) {
    if (sm.on[i] == 0) continue;
    if (sm.from_start[i] < kEndSamples || sm.to_end[i] < kEndSamples) {
      sample_of.insert(sample_of.end(), {i, i});
      dir.push_back({sm.c[i] * sm.normal[i].x, sm.c[i] * sm.normal[i].y});
      dir.push_back({sm.c[i] * sm.tangent[i].x, sm.c[i] * sm.tangent[i].y});
    } else {
      base[i].x += sm.c[i] * sm.normal[i].x;
      base[i].y += sm.c[i] * sm.normal[i].y;
    }
  }
  std::vector<EndVec> base_out(n);
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t i = 0; i < m && i <= k; ++i) {
      base_out[k].x += h_[i] * base[k - i].x;
      base_out[k].y += h_[i] * base[k - i].y;
    }
  const auto f = static_cast<Eigen::Index>(dir.size());
  const std::size_t first_valid = m - 1;
  const auto rows = static_cast<Eigen::Index>(n - first_valid);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(f), weight = Eigen::VectorXd::Ones(rows);
  Eigen::VectorXd best_u = u;
  double best = std::numeric_limits<double>::infinity();
  Eigen::MatrixXd a(rows, f);
  Eigen::VectorXd rhs(rows);
  for (int it = 0; it <= iterations_ && f > 0; ++it) {
    a.setZero();
    double worst = 0.0;
    for (Eigen::Index r = 0; r < rows; ++r) {
      const std::size_t k = first_valid + static_cast<std::size_t>(r);
      EndVec y = base_out[k];
      for (Eigen::Index q = 0; q < f; ++q) {
        const std::size_t i = sample_of[static_cast<std::size_t>(q)];
        if (i > k || k - i >= m) continue;
        const double w = h_[k - i] * u[q];
        y.x += w * dir[static_cast<std::size_t>(q)].x;
        y.y += w * dir[static_cast<std::size_t>(q)].y;
      }
      const auto [d, g] = sm.distance(y, sm.sbar[k]);
      worst = std::max(worst, d);
      for (Eigen::Index q = 0; q < f; ++q) {
        const std::size_t i = sample_of[static_cast<std::size_t>(q)];
        if (i > k || k - i >= m) continue;
        a(r, q) = h_[k - i] * end_dot(g, dir[static_cast<std::size_t>(q)]);
      }
      rhs[r] = d - a.row(r).dot(u);
    }
    if (worst < best) {  // the reweighting can overshoot: keep the best pass
      best = worst;
      best_u = u;
    }
    if (it == iterations_) break;
    Eigen::MatrixXd normal = a.transpose() * weight.asDiagonal() * a;
    normal.diagonal().array() += lambda_ * sm.c_planned * sm.c_planned;
    u = normal.ldlt().solve(-(a.transpose() * weight.asDiagonal() * rhs));
    const Eigen::VectorXd e = (a * u + rhs).cwiseAbs();
    const double top = e.maxCoeff();
    if (!(top > 0.0)) break;
    weight =
        weight.cwiseProduct((e / top).array().matrix() + Eigen::VectorXd::Constant(rows, 1e-3));
    weight /= weight.mean();
  }
  u = best_u;
  ArcOffsets off{std::vector<double>(n, 0.0), std::vector<double>(n, 0.0)};
  for (std::size_t i = 0; i < n; ++i)
    if (sm.on[i] != 0) off.radial_mm[i] = sm.c[i];
  for (Eigen::Index q = 0; q < f; ++q) {
    const std::size_t i = sample_of[static_cast<std::size_t>(q)];
    (q % 2 == 0 ? off.radial_mm : off.along_mm)[i] = u[q] * sm.c[i];
  }
  return off;
}

double ArcEndFit::worst_fraction(const ArcRun& run, const ArcOffsets& off) const {
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
    worst = std::max(worst, sm.distance(y, sm.sbar[k]).first);
  }
  return worst / sm.loss_planned;
}

}  // namespace gm
