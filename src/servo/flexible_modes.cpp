// FlexibleModes: each mode's transition matrix, by the matrix exponential.
#include "servo/flexible_modes.hpp"

#include "common/status.hpp"

#include <fmt/format.h>
#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include <cmath>
#include <numbers>

namespace gm {

FlexibleModes::FlexibleModes(const std::vector<double>& frequency_hz,
                             const std::vector<double>& damping, double h_s, double start) {
  if (frequency_hz.size() != damping.size())
    throw InputError(fmt::format("modes: {} frequencies but {} damping ratios", frequency_hz.size(),
                                 damping.size()));
  if (frequency_hz.size() > static_cast<std::size_t>(kMaxModes))
    throw InputError(fmt::format("modes: at most {} (got {})", kMaxModes, frequency_hz.size()));
  if (!(h_s > 0.0)) throw InputError("modes: the servo period must be > 0");
  n_ = static_cast<int>(frequency_hz.size());
  inv_h_ = 1.0 / h_s;
  prev_in_ = start;
  for (int i = 0; i < n_; ++i) {
    const double f = frequency_hz[static_cast<std::size_t>(i)];
    const double z = damping[static_cast<std::size_t>(i)];
    if (!(f > 0.0 && std::isfinite(f)) || !(z >= 0.0 && std::isfinite(z)))
      throw InputError(
          fmt::format("modes: frequency must be > 0 Hz and damping >= 0 (got {} Hz, {})", f, z));
    const double w = 2.0 * std::numbers::pi * f;
    Eigen::Matrix2d a;
    a << 0.0, 1.0, -w * w, -2.0 * z * w;
    const Eigen::Matrix2d phi = (a * h_s).exp();
    Mode& m = modes_[static_cast<std::size_t>(i)];
    m.p00 = phi(0, 0);
    m.p01 = phi(0, 1);
    m.p10 = phi(1, 0);
    m.p11 = phi(1, 1);
    m.y = start;
    m.v = 0.0;
  }
}

}  // namespace gm
