// Structural modes between motor and table: two-mass oscillators the motor position drives.
#pragma once

#include <array>
#include <vector>

namespace gm {

/// Zero or more structural modes between the motor and the table (a two-mass model per mode:
/// the table coupled to the motor side by a spring and a damper), in series: the first is driven
/// by the motor position, each next one by the previous one's output, the last one's output is
/// the table. Mode i: ÿ = ω_i² (x − y) + 2 ζ_i ω_i (ẋ − ẏ), x its input, y its output, unit
/// static gain. The motor drives the modes and does not feel them (their reaction on the motor
/// is taken as part of the plant). Discretised exactly for an input linear over each servo
/// period h: with slope s = (x1 − x0)/h the deflection e = y − x obeys ë = −ω² e − 2ζω ė, so
/// [e; ė − s] advances by Φ = exp([[0, 1], [−ω², −2ζω]] h). Cascaded modes take the previous
/// mode's output as linear over h too. Allocates only in the constructor.
class FlexibleModes {
 public:
  static constexpr int kMaxModes = 4;
  FlexibleModes() = default;
  /// frequency_hz > 0 and damping ≥ 0 of each mode (same length, at most kMaxModes), servo
  /// period h_s > 0; `start` is the input (and table) position at rest. Throws gm::InputError.
  FlexibleModes(const std::vector<double>& frequency_hz, const std::vector<double>& damping,
                double h_s, double start);
  int count() const { return n_; }
  /// One servo period: the input moved from the last value to `x1` (linearly); returns the
  /// output (table) position at the end of the period.
  double step(double x1) {
    double x0 = prev_in_;
    prev_in_ = x1;
    for (int i = 0; i < n_; ++i) {
      Mode& m = modes_[static_cast<std::size_t>(i)];
      const double s = (x1 - x0) * inv_h_;
      const double e = m.y - x0, d = m.v - s;
      const double e1 = m.p00 * e + m.p01 * d, d1 = m.p10 * e + m.p11 * d;
      x0 = m.y;  // this mode's output over the period is the next one's input
      m.y = x1 + e1;
      m.v = s + d1;
      x1 = m.y;
    }
    return x1;
  }
  /// Output (table) position now; the input's when there are no modes.
  double output() const { return n_ > 0 ? modes_[static_cast<std::size_t>(n_ - 1)].y : prev_in_; }

 private:
  struct Mode {
    double p00 = 1, p01 = 0, p10 = 0, p11 = 1;  ///< Φ
    double y = 0, v = 0;                        ///< output position and velocity
  };
  std::array<Mode, kMaxModes> modes_{};
  int n_ = 0;
  double inv_h_ = 0.0;
  double prev_in_ = 0.0;
};

}  // namespace gm
