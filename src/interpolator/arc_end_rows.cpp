// ArcEndFit: the 2-D offsets on a pre-compensated arc's first samples, fitted for the least worst
// distance of the Acc/Dec output from the path, and that distance measured.
#include "interpolator/arc_end_rows.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace gm {

namespace {

constexpr int kEndRows = ArcEndRows::kSamples;

struct EndVec {
  double x = 0.0, y = 0.0;
};

double end_dot(EndVec a, EndVec b) {
  return a.x * b.x + a.y * b.y;
}

// Distance of point y from the path (the half-line y = 0, x <= 0, then the unit circle about
// (0, 1) once the point is past the arc's start or the window's mean has run a quarter turn
// along it) and its gradient.
std::pair<double, EndVec> end_distance(EndVec p, double sbar) {
  double d;
  EndVec g;
  if (p.x <= 0.0) {
    d = std::abs(p.y);
    g = {0.0, p.y < 0.0 ? -1.0 : 1.0};
  } else {
    d = std::hypot(p.x, p.y);
    g = d > 0.0 ? EndVec{p.x / d, p.y / d} : EndVec{};
  }
  if (p.x >= 0.0 || sbar > 0.5 * std::numbers::pi) {
    const double r = std::hypot(p.x, p.y - 1.0);
    const double dc = std::abs(r - 1.0);
    if (dc < d && r > 0.0) {
      const double sign = r >= 1.0 ? 1.0 : -1.0;
      d = dc;
      g = {sign * p.x / r, sign * (p.y - 1.0) / r};
    }
  }
  return {d, g};
}

}  // namespace

ArcEndSpeeds ArcEndSpeeds::constant(double x, double phase, int window) {
  ArcEndSpeeds s;
  s.x.assign(static_cast<std::size_t>(6 * window), x);
  s.join = 2 * window;
  s.phase = phase;
  return s;
}

struct ArcEndFit::Run {
  int n = 0;
  std::vector<double> s, sbar, c;  // path position, window's mean position, steady correction
  std::vector<EndVec> normal, tangent, base_out;  // the output of the command without the free part
  std::vector<EndVec> point;
  int free_count = 0;     // arc samples with free offsets (at most kEndRows)
  double c_arc = 0.0;     // steady correction at the arc's rate
  double loss_arc = 0.0;  // steady loss 1 − A at the arc's rate
};

ArcEndFit::ArcEndFit(std::vector<double> weights, double lambda, int iterations)
    : h_(std::move(weights)), lambda_(lambda), iterations_(iterations) {
  for (std::size_t i = 0; i < h_.size(); ++i) centre_ += static_cast<double>(i) * h_[i];
}

double ArcEndFit::gain(double x) const {
  double a = 0.0;
  for (std::size_t i = 0; i < h_.size(); ++i)
    a += h_[i] * std::cos((static_cast<double>(i) - centre_) * x);
  return a;
}

ArcEndRows ArcEndFit::linear_blend(double phase) {
  ArcEndRows r;
  for (int j = 0; j < kEndRows; ++j) r.radial[j] = std::min(1.0, (j + phase) / 2.0);
  return r;
}

ArcEndFit::Run ArcEndFit::prepare(const ArcEndSpeeds& sp) const {
  Run run;
  run.n = static_cast<int>(sp.x.size());
  const auto n = static_cast<std::size_t>(run.n);
  const auto m = h_.size();
  run.s.resize(n);
  double acc = 0.0;
  for (std::size_t i = 0; i < n; ++i) run.s[i] = acc += sp.x[i];
  const double shift = run.s[static_cast<std::size_t>(sp.join)] - sp.phase * sp.x[sp.join];
  for (double& v : run.s) v -= shift;
  run.c.assign(n, 0.0);
  run.normal.assign(n, {});
  run.tangent.assign(n, {1.0, 0.0});
  run.point.resize(n);
  double x_arc = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double s = run.s[i];
    if (s <= 0.0) {
      run.point[i] = {s, 0.0};
      continue;
    }
    run.point[i] = {std::sin(s), 1.0 - std::cos(s)};
    run.normal[i] = {std::sin(s), -std::cos(s)};
    run.tangent[i] = {std::cos(s), std::sin(s)};
    run.c[i] = 1.0 / gain(sp.x[i]) - 1.0;
    x_arc = std::max(x_arc, sp.x[i]);
  }
  run.c_arc = 1.0 / gain(x_arc) - 1.0;
  run.loss_arc = 1.0 - gain(x_arc);
  run.free_count = std::min(kEndRows, run.n - sp.join);
  // The command without the free part: the path, plus the steady correction past the free
  // samples; its output and the window's mean position.
  std::vector<EndVec> base(n);
  for (std::size_t i = 0; i < n; ++i) {
    base[i] = run.point[i];
    if (static_cast<int>(i) >= sp.join + run.free_count) {
      base[i].x += run.c[i] * run.normal[i].x;
      base[i].y += run.c[i] * run.normal[i].y;
    }
  }
  run.base_out.assign(n, {});
  run.sbar.assign(n, 0.0);
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t i = 0; i < m && i <= k; ++i) {
      run.base_out[k].x += h_[i] * base[k - i].x;
      run.base_out[k].y += h_[i] * base[k - i].y;
      run.sbar[k] += h_[i] * run.s[k - i];
    }
  return run;
}

ArcEndRows ArcEndFit::fit(const ArcEndSpeeds& sp) const {
  const Run run = prepare(sp);
  const int m = static_cast<int>(h_.size());
  const int f = 2 * run.free_count;
  // Unknown q: sample join + q/2, radial (q even) or tangential (q odd), in units of its c.
  std::vector<EndVec> dir(static_cast<std::size_t>(f));
  for (int q = 0; q < f; ++q) {
    const auto i = static_cast<std::size_t>(sp.join + q / 2);
    const EndVec d = q % 2 == 0 ? run.normal[i] : run.tangent[i];
    dir[static_cast<std::size_t>(q)] = {run.c[i] * d.x, run.c[i] * d.y};
  }
  const int first_valid = m - 1;
  const int rows = run.n - first_valid;
  std::vector<double> weight(static_cast<std::size_t>(rows), 1.0);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(f);
  Eigen::MatrixXd a(rows, f);
  Eigen::VectorXd rhs(rows);
  for (int it = 0; it < iterations_; ++it) {
    a.setZero();
    for (int r = 0; r < rows; ++r) {
      const int k = first_valid + r;
      EndVec y = run.base_out[static_cast<std::size_t>(k)];
      for (int q = 0; q < f; ++q) {
        const int lag = k - (sp.join + q / 2);
        if (lag < 0 || lag >= m) continue;
        const double w = h_[static_cast<std::size_t>(lag)] * u[q];
        y.x += w * dir[static_cast<std::size_t>(q)].x;
        y.y += w * dir[static_cast<std::size_t>(q)].y;
      }
      const auto [d, g] = end_distance(y, run.sbar[static_cast<std::size_t>(k)]);
      for (int q = 0; q < f; ++q) {
        const int lag = k - (sp.join + q / 2);
        if (lag < 0 || lag >= m) continue;
        a(r, q) = h_[static_cast<std::size_t>(lag)] * end_dot(g, dir[static_cast<std::size_t>(q)]);
      }
      rhs[r] = d - a.row(r).dot(u);
    }
    const Eigen::VectorXd w = Eigen::Map<const Eigen::VectorXd>(weight.data(), rows);
    Eigen::MatrixXd normal = a.transpose() * w.asDiagonal() * a;
    normal.diagonal().array() += lambda_ * run.c_arc * run.c_arc;
    u = normal.ldlt().solve(-(a.transpose() * w.asDiagonal() * rhs));
    const Eigen::VectorXd e = (a * u + rhs).cwiseAbs();
    const double top = e.maxCoeff();
    double mean = 0.0;
    for (int r = 0; r < rows; ++r) {
      weight[static_cast<std::size_t>(r)] *= e[r] / top + 1e-3;
      mean += weight[static_cast<std::size_t>(r)];
    }
    mean /= rows;
    for (double& v : weight) v /= mean;
  }
  ArcEndRows out;
  for (int j = 0; j < kEndRows; ++j) out.radial[j] = 1.0;
  for (int j = 0; j < run.free_count; ++j) {
    out.radial[j] = u[2 * j];
    out.tangential[j] = u[2 * j + 1] * sp.x[static_cast<std::size_t>(sp.join + j)];
  }
  return out;
}

double ArcEndFit::worst_fraction(const ArcEndSpeeds& sp, const ArcEndRows& rows) const {
  const Run run = prepare(sp);
  const auto n = static_cast<std::size_t>(run.n);
  const auto m = h_.size();
  std::vector<EndVec> cmd(n);
  for (std::size_t i = 0; i < n; ++i) {
    cmd[i] = run.point[i];
    if (!(run.s[i] > 0.0)) continue;
    const auto j = static_cast<int>(i) - sp.join;
    double radial = run.c[i], along = 0.0;
    if (j < ArcEndRows::kSamples) {
      radial *= rows.radial[static_cast<std::size_t>(j)];
      along = rows.tangential[static_cast<std::size_t>(j)] * run.c[i] / sp.x[i];
    }
    cmd[i].x += radial * run.normal[i].x + along * run.tangent[i].x;
    cmd[i].y += radial * run.normal[i].y + along * run.tangent[i].y;
  }
  double worst = 0.0;
  for (std::size_t k = m - 1; k < n; ++k) {
    EndVec y;
    for (std::size_t i = 0; i < m; ++i) {
      y.x += h_[i] * cmd[k - i].x;
      y.y += h_[i] * cmd[k - i].y;
    }
    worst = std::max(worst, end_distance(y, run.sbar[k]).first);
  }
  return worst / run.loss_arc;
}

}  // namespace gm
