// Per-axis servo: encoder (motor or table), P position loop, PI velocity loop, ZOH plant.
#include "servo/servo_axis.hpp"

#include "common/rounding.hpp"
#include "common/status.hpp"
#include "common/units.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace gm {

ServoAxis::ServoAxis(const AxisConfig& axis, double period_s, int substeps, std::int64_t start_blu)
    : plant_(axis.plant_num, axis.plant_den, axis.plant_blu_s_per_unit,
             substeps >= 1 && period_s > 0.0 ? period_s / substeps : 1.0),
      form_(axis.kv_form),
      kvp_(axis.kvp),
      kvi_(axis.kvi),
      kp_(axis.kp_1_s),
      h_s_(substeps >= 1 ? period_s / substeps : period_s),
      kv_period_s_(axis.kv_period_s),
      substeps_(substeps),
      start_blu_(start_blu),
      prev_count_(start_blu),
      prev_ref_(start_blu),
      table_encoder_(axis.encoder == EncoderSite::Table) {
  if (!(period_s > 0.0))
    throw InputError(fmt::format("servo: period must be > 0 (got {})", period_s));
  if (substeps < 1)
    throw InputError(fmt::format("servo: substeps must be >= 1 (got {})", substeps));
  if (!(kv_period_s_ > 0.0))
    throw InputError(fmt::format("servo: kv_period_s must be > 0 (got {})", kv_period_s_));
  if (!(kvp_ >= 0.0) || !(kvi_ >= 0.0) || !(kp_ > 0.0))
    throw InputError("servo: gains must be kvp >= 0, kvi >= 0, kp_1_s > 0");
  n_per_unit_ = axis.drive_N_per_unit;
  if (n_per_unit_ == 0.0) {
    if (plant_.accel_gain_blu_s2() == 0.0)
      throw InputError("servo: drive_N_per_unit must be given for a plant of relative degree > 1");
    // N per unit from m/s² (kg), or N·m per unit from rad/s² (kg·m²) on a rotary axis.
    const double si_per_unit = axis.rotary ? 1.0 / units::kDegPerRadian : 1e-3;
    n_per_unit_ = axis.mass_kg * plant_.accel_gain_blu_s2() * axis.blu_mm * si_per_unit;
  }
  if (!(n_per_unit_ > 0.0))
    throw InputError(fmt::format("servo: drive_N_per_unit must be > 0 (got {})", n_per_unit_));
  u_max_ = axis.f_max_N / n_per_unit_;
  u_coulomb_ = axis.coulomb_N / n_per_unit_;
  half_backlash_ = 0.5 * axis.backlash_blu;
  kv_over_h_ = kv_period_s_ / h_s_;
  h_over_kv_ = h_s_ / kv_period_s_;
  if (!std::isfinite(axis.ff1) || !std::isfinite(axis.ff2_s))
    throw InputError("servo: ff1 and ff2_s must be finite");
  ff1_kv_ = axis.ff1 * kv_period_s_ / period_s;
  ff2_kv_ = axis.ff2_s * kv_period_s_ / (period_s * period_s);
  if (!axis.mode_hz.empty() || !axis.mode_damping.empty())
    modes_ = FlexibleModes(axis.mode_hz, axis.mode_damping, h_s_, 0.0);
}

std::int64_t ServoAxis::motor_count() const {
  return start_blu_ + round_half_away(plant_.position_blu());
}

std::int64_t ServoAxis::count_now() const {
  if (table_encoder_) [[unlikely]]
    return start_blu_ + round_half_away(modes_.count() > 0 ? modes_.output() : table_rel_);
  return motor_count();
}

std::int64_t ServoAxis::step(std::int64_t ref_blu) {
  if (!have_ref_) {
    prev_ref_ = ref_blu;
    have_ref_ = true;
  }
  const std::int64_t count0 = count_now();
  const std::int64_t d = ref_blu - prev_ref_;
  const double delta = static_cast<double>(d);
  // Feedforward of the line the substeps extrapolate along: its velocity (ref[k]-ref[k-1])/T
  // and the change of that velocity, constant over the period. Gains 0 add +-0.0: the loop
  // without feedforward is bit for bit what it was.
  const double ff = ff1_kv_ * delta + ff2_kv_ * static_cast<double>(d - prev_delta_);
  saturated_ = false;
  // j = 0 gives ref + 0.0 = ref exactly, so one substep needs no extrapolation arithmetic.
  servo_sample(count0, static_cast<double>(ref_blu), ff, true,
               0.0);  // the plant has not moved since count0
  for (int j = 1; j < substeps_; ++j) {
    const double r = static_cast<double>(ref_blu) + delta * j / substeps_;
    servo_sample(count_now(), r, ff, true, 0.0);
  }
  prev_ref_ = ref_blu;
  prev_delta_ = d;
  // An unstable loop (plant, gains or period) sends the motor off without bound; stop before
  // the counts leave the range where they are exact and ref - count cannot overflow.
  if (!(std::fabs(plant_.position_blu()) < kMaxPositionBlu))
    throw InputError(divergence_message(plant_.position_blu(), ref_blu));
  return count0;
}

std::string ServoAxis::divergence_message(double position_blu, std::int64_t ref_blu) {
  return fmt::format(
      "servo diverged: the motor is at {:.3g} BLU after following a reference of {} BLU; "
      "the loop is unstable with this plant, these gains and this period",
      position_blu, ref_blu);
}

void ServoAxis::step_velocity(double v_ref_blu_s) {
  saturated_ = false;
  for (int j = 0; j < substeps_; ++j) servo_sample(count_now(), 0.0, 0.0, false, v_ref_blu_s);
}

inline void ServoAxis::servo_sample(std::int64_t count, double pos_ref_blu, double ff,
                                    bool position_loop, double v_ref_blu_s) {
  // Velocity feedback and reference in encoder counts per kv_period_s; the velocity from the
  // motor's encoder (the same count unless the position encoder is on the table).
  const std::int64_t vcount = table_encoder_ ? motor_count() : count;
  const double y = static_cast<double>(vcount - prev_count_) * kv_over_h_;
  prev_count_ = vcount;
  const double vref_blu_s =
      position_loop ? kp_ * (pos_ref_blu - static_cast<double>(count)) : v_ref_blu_s;
  const double r_v = vref_blu_s * kv_period_s_ + ff;
  const double e = r_v - y;
  const double di = e * h_over_kv_;
  double integ = integ_ + di;
  double u = form_ == VelocityLoopForm::Ip ? kvi_ * integ - kvp_ * y : kvp_ * e + kvi_ * integ;
  if (u > u_max_ || u < -u_max_) {
    saturated_ = true;
    const double sat = std::clamp(u, -u_max_, u_max_);
    // Conditional integration: keep the old sum if the new one pushes further into the limit.
    if ((u > u_max_ && di > 0.0) || (u < -u_max_ && di < 0.0)) integ = integ_;
    u = sat;
  }
  integ_ = integ;
  u_ = u;
  plant_step(u);
  // Lost motion: the table stays put until the motor has crossed the dead band.
  const double p = plant_.position_blu();
  if (p - table_rel_ > half_backlash_)
    table_rel_ = p - half_backlash_;
  else if (p - table_rel_ < -half_backlash_)
    table_rel_ = p + half_backlash_;
  if (modes_.count() > 0) [[unlikely]]
    modes_.step(table_rel_);
}

inline void ServoAxis::plant_step(double u) {
  if (u_coulomb_ <= 0.0) {
    plant_.step(u);
    return;
  }
  // Coulomb friction as a drive-unit disturbance u_c sign(v), with stiction at v = 0.
  const double v0 = plant_.velocity_blu_s();
  if (v0 == 0.0) {
    if (std::abs(u) <= u_coulomb_) return;  // stuck: static friction balances the drive
    plant_.step(u - std::copysign(u_coulomb_, u));
    return;
  }
  plant_.step(u - std::copysign(u_coulomb_, v0));
  const double v1 = plant_.velocity_blu_s();
  if ((v0 > 0.0 && v1 < 0.0) || (v0 < 0.0 && v1 > 0.0)) plant_.stop();  // sticks at reversal
}

}  // namespace gm
