// Exact zero-order-hold discretisation of a velocity plant num(s)/den(s) plus its position
// integral.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace gm {

/// The plant G(s) = num(s)/den(s) (drive command -> motor velocity, plant units) in controllable
/// canonical form, augmented with the position state p' = scale * v, discretised exactly for a
/// drive command held constant over one servo period h (ZOH, Eigen matrix exponential of the
/// augmented matrix [[A B];[0 0]] * h). State z = [x (n plant states); p (BLU)].
/// Requirements: den[0] != 0, strictly proper (num.size() < den.size() after dropping leading
/// zeros of num), order <= kMaxOrder. step() allocates nothing.
class DiscretePlant {
 public:
  static constexpr int kMaxOrder = 6;
  static constexpr int kMaxState = kMaxOrder + 1;
  using State = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxState, 1>;
  using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxState, kMaxState>;

  /// num/den highest power first; scale_blu_s_per_unit converts plant output to BLU/s;
  /// period_s = h > 0. Throws gm::InputError on an invalid plant.
  DiscretePlant(const std::vector<double>& num, const std::vector<double>& den,
                double scale_blu_s_per_unit, double period_s);

  int order() const { return n_; }
  /// Advances one period with drive command u held constant (ZOH).
  /// z ← Ad z + Bd u, each row summed in column order (the order Eigen's product uses).
  /// Plants of order 1 and 2 (the usual ones) run a loop the compiler unrolls; the sums are the
  /// same, term by term, as the general loop's. Always inlined into the servo's sample (whether
  /// the compiler inlines it otherwise depends on which files a unity batch holds: 8 M
  /// instructions in 10,000 blocks when it did not).
  [[gnu::always_inline]] inline void step(double u) {
    switch (n_) {
      case 1:
        step_sized<2>(u);
        return;
      case 2:
        step_sized<3>(u);
        return;
      default:
        step_general(u);
        return;
    }
  }
  /// Motor velocity, BLU/s (C x, scaled).
  double velocity_blu_s() const { return c_.dot(z_.head(n_)); }
  /// Position relative to the start, BLU (continuous, not quantised).
  double position_blu() const { return z_[n_]; }
  /// Sets the plant's internal (velocity) states to zero; the position is kept (stiction).
  void stop() { z_.head(n_).setZero(); }
  /// DC gain of the plant (velocity BLU/s per drive unit at steady state).
  double dc_gain_blu_s() const { return dc_gain_; }
  /// High-frequency gain num/den leading ratio times the scale when the relative degree is 1:
  /// acceleration in BLU/s^2 per drive unit; 0 when the relative degree is higher.
  double accel_gain_blu_s2() const { return accel_gain_; }

  const Matrix& ad() const { return ad_; }
  const State& bd() const { return bd_; }
  /// The state z = [x; p] (length order() + 1), for ServoBank, which steps it in SIMD lanes.
  const State& state() const { return z_; }
  void set_state(const State& z) { z_ = z; }

 private:
  template <int M>
  void step_sized(double u) {
    const double* a = ad_.data();  // column-major, leading dimension M
    double* z = z_.data();
    double next[M];
    for (int i = 0; i < M; ++i) {
      double s = a[i] * z[0];
      for (int j = 1; j < M; ++j) s += a[j * M + i] * z[j];
      next[i] = s + bd_[i] * u;
    }
    for (int i = 0; i < M; ++i) z[i] = next[i];
  }
  void step_general(double u) {
    const int m = n_ + 1;
    const double* a = ad_.data();
    for (int i = 0; i < m; ++i) {
      double s = a[i] * z_[0];
      for (int j = 1; j < m; ++j) s += a[j * m + i] * z_[j];
      next_[i] = s + bd_[i] * u;
    }
    z_.swap(next_);
  }

  int n_ = 0;
  Matrix ad_;
  State bd_;
  State c_;     ///< length n_, output row (scaled to BLU/s)
  State z_;     ///< state, length n_ + 1
  State next_;  ///< scratch for step(), length n_ + 1
  double dc_gain_ = 0.0;
  double accel_gain_ = 0.0;
};

}  // namespace gm
