// A servo loop's transfer function identified from its step response, and the zero-phase-error
// tracking taps that take its dynamics out of the command.
#include "planner/loop_shaping.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace gm {

LoopModel identify_loop(const std::vector<double>& s) {
  // The recurrence's a_1..a_n in least squares: −g_k = Σ_{j≥1} a_j·g_{k−j} for k > n.
  constexpr int kMaxLoopOrder = 12, kFitLen = 2048;
  constexpr double kModelTol = 1e-9;
  const int len = static_cast<int>(s.size()), fit = std::min(len, kFitLen);
  std::vector<double> g(s.size());
  for (std::size_t k = 0; k < s.size(); ++k) g[k] = s[k] - (k ? s[k - 1] : 0.0);
  const auto at = [&g](int k) { return k >= 0 ? g[static_cast<std::size_t>(k)] : 0.0; };
  for (int n = 1; n <= kMaxLoopOrder && 2 * n + 2 < fit; ++n) {
    Eigen::MatrixXd M(fit - n - 1, n);
    Eigen::VectorXd r(fit - n - 1);
    for (int k = n + 1; k < fit; ++k) {
      for (int j = 1; j <= n; ++j) M(k - n - 1, j - 1) = at(k - j);
      r[k - n - 1] = -at(k);
    }
    const Eigen::VectorXd x = M.colPivHouseholderQr().solve(r);
    if (!x.allFinite()) continue;
    LoopModel model;
    model.a.assign(1, 1.0);
    for (int j = 0; j < n; ++j) model.a.push_back(x[j]);
    for (int k = 0; k <= n; ++k) {
      double bk = 0.0;
      for (int j = 0; j <= k; ++j) bk += model.a[static_cast<std::size_t>(j)] * at(k - j);
      model.b.push_back(bk);
    }
    // The model's own step response against s over its whole length.
    std::vector<double> y(static_cast<std::size_t>(n), 0.0);  // y_{k−1} .. y_{k−n}
    double worst = 0.0;
    for (int k = 0; k < len && worst <= kModelTol; ++k) {
      double yk = 0.0;
      for (int j = 0; j <= n && j <= k; ++j) yk += model.b[static_cast<std::size_t>(j)];
      for (int j = 1; j <= n; ++j)
        yk -= model.a[static_cast<std::size_t>(j)] * y[static_cast<std::size_t>(j - 1)];
      std::rotate(y.rbegin(), y.rbegin() + 1, y.rend());
      y[0] = yk;
      worst = std::max(worst, std::abs(yk - s[static_cast<std::size_t>(k)]));
    }
    if (worst <= kModelTol) return model;
  }
  return {};
}

std::vector<double> zpetc_weights(const LoopModel& loop) {
  double peak = 0.0, dc = 0.0;  // max |b_k|, B(1)
  for (const double b : loop.b) peak = std::max(peak, std::abs(b)), dc += b;
  if (!(peak > 0.0) || !(std::abs(dc) > 1e-6 * peak)) return {};
  // B′: b_first .. b_{last−1}; F_{i+(last−1−j)} += a_i·b_j / B(1)².
  std::size_t first = 0, last = loop.b.size();
  while (std::abs(loop.b[first]) <= 1e-12 * peak) ++first;
  while (std::abs(loop.b[last - 1]) <= 1e-12 * peak) --last;
  std::vector<double> f(loop.a.size() + (last - first) - 1, 0.0);
  for (std::size_t i = 0; i < loop.a.size(); ++i)
    for (std::size_t j = first; j < last; ++j)
      f[i + (last - 1 - j)] += loop.a[i] * loop.b[j] / (dc * dc);
  return f;
}

}  // namespace gm
