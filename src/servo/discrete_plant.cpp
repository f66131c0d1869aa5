// Exact ZOH discretisation of the velocity plant (matrix exponential of the augmented system).
#include "servo/discrete_plant.hpp"

#include "common/status.hpp"

#include <fmt/format.h>
#include <unsupported/Eigen/MatrixFunctions>

#include <cmath>

namespace gm {

DiscretePlant::DiscretePlant(const std::vector<double>& num_in, const std::vector<double>& den,
                             double scale_blu_s_per_unit, double period_s) {
  std::vector<double> num = num_in;
  while (!num.empty() && num.front() == 0.0) num.erase(num.begin());
  if (den.empty() || den.front() == 0.0 || !std::isfinite(den.front()))
    throw InputError("plant: the leading denominator coefficient must be finite and non-zero");
  const int n = static_cast<int>(den.size()) - 1;
  if (n < 1 || n > kMaxOrder)
    throw InputError(fmt::format("plant: order must be 1..{} (got {})", kMaxOrder, n));
  if (num.empty()) throw InputError("plant: numerator is zero");
  if (static_cast<int>(num.size()) > n)
    throw InputError("plant: must be strictly proper (numerator degree < denominator degree)");
  for (double c : num)
    if (!std::isfinite(c)) throw InputError("plant: numerator coefficients must be finite");
  for (double c : den)
    if (!std::isfinite(c)) throw InputError("plant: denominator coefficients must be finite");
  if (!(period_s > 0.0)) throw InputError("plant: servo period must be > 0");
  if (!(scale_blu_s_per_unit > 0.0)) throw InputError("plant: velocity scale must be > 0");
  n_ = n;

  // Controllable canonical form of num/den normalised by den[0]:
  // x' = A x + B u, A = companion (last row -a_n..-a_1), B = e_n, v = C x.
  const double d0 = den.front();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n + 1, n + 1);  // augmented with position
  for (int i = 0; i + 1 < n; ++i) a(i, i + 1) = 1.0;
  for (int j = 0; j < n; ++j) a(n - 1, j) = -den[static_cast<std::size_t>(n - j)] / d0;  // -a_{n-j}
  c_ = State::Zero(n);
  const int m = static_cast<int>(num.size());  // num degree m-1 < n
  for (int k = 0; k < m; ++k)                  // coefficient of s^k is num[m-1-k]; multiplies x_{k}
    c_[k] = num[static_cast<std::size_t>(m - 1 - k)] / d0 * scale_blu_s_per_unit;
  for (int j = 0; j < n; ++j) a(n, j) = c_[j];  // p' = v (BLU/s)

  // Augmented-matrix trick: exp([[A_aug B_aug];[0 0]] h) = [[Ad Bd];[0 1]].
  Eigen::MatrixXd big = Eigen::MatrixXd::Zero(n + 2, n + 2);
  big.topLeftCorner(n + 1, n + 1) = a * period_s;
  big(n - 1, n + 1) = period_s;  // B = e_n
  const Eigen::MatrixXd e = big.exp();
  ad_ = e.topLeftCorner(n + 1, n + 1);
  bd_ = e.block(0, n + 1, n + 1, 1);
  z_ = State::Zero(n + 1);
  next_ = State::Zero(n + 1);

  const double an = den.back() / d0;
  const double bn = num.back() / d0;
  dc_gain_ = an != 0.0 ? bn / an * scale_blu_s_per_unit : HUGE_VAL;
  accel_gain_ = (m == n) ? num.front() / d0 * scale_blu_s_per_unit : 0.0;
}

}  // namespace gm
