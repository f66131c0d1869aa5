// One axis of the servo: P position loop, PI velocity loop, plant, encoder on motor or table.
#pragma once

#include "machine/machine.hpp"
#include "servo/discrete_plant.hpp"
#include "servo/flexible_modes.hpp"

#include <cstdint>
#include <string>

namespace gm {

/// Discrete servo model of one axis (Chen & Lee 1998, section 7, Fig. 16), run at the servo
/// period h = T / substeps. Per servo sample, in this order:
///  1. encoder: count = start_blu + round(motor position) — rounding, i.e. the count changes
///     half-way between two BLU (an incremental encoder whose zero sits half a count off);
///  2. velocity feedback y = (count - previous count) * kv_period_s / h, counts per kv_period_s
///     (the backward difference of the encoder: what a digital servo measures);
///  3. position loop: r_v = (Kp * (ref - count) + FF1 v_ref + FF2 a_ref) * kv_period_s (same
///     unit as y); within one period T the reference is extrapolated linearly from the last two
///     references (ref[k] + (ref[k]-ref[k-1]) j/substeps), exact for constant velocity, and the
///     feedforward takes that line's velocity v_ref = (ref[k]-ref[k-1])/T and the acceleration
///     a_ref = (v_ref[k]-v_ref[k-1])/T, both held over the period (LinuxCNC's pid at period T);
///  4. velocity loop: I += (r_v - y) * h / kv_period_s; Ip form u = Kvi I - Kvp y, Pi form
///     u = Kvp (r_v - y) + Kvi I; u saturates at +-u_max = f_max_N / drive_N_per_unit with
///     conditional integration (the sum is not updated while it would deepen saturation);
///  5. plant: u held over h (exact ZOH), minus Coulomb friction (stick-slip) if enabled;
///  6. lost motion: the table follows the motor inside a dead band of width backlash_blu;
///  7. structural modes (mode_hz, mode_damping): the table follows that through two-mass
///     oscillators (FlexibleModes).
/// The position encoder (step 1) reads the motor (`encoder = "motor"`, semi-closed loop, the
/// paper's) or the table after 6 and 7 (`encoder = "table"`, full-closed loop: a linear scale,
/// so the position loop sees the lost motion and the modes); the velocity feedback (step 2)
/// always differences the motor's encoder.
/// The drive command u is in plant input units (volts in the paper: 10 V = rated torque).
/// Construction may allocate; step() allocates nothing (but the exception when the loop diverges).
class ServoAxis {
 public:
  /// step() throws gm::InputError once the motor is this far (BLU) from its start: the loop
  /// has diverged (1e15 BLU is a million km at 1 µm; counts stay exact below 2^53).
  static constexpr double kMaxPositionBlu = 1e15;

  /// axis: plant, gains and mapping; period_s = T > 0; substeps >= 1; start_blu: the motor and
  /// the table start at rest at this count. Throws gm::InputError on an invalid configuration.
  ServoAxis(const AxisConfig& axis, double period_s, int substeps, std::int64_t start_blu);

  /// One interpolation period T with position reference ref_blu (the Acc/Dec output for this
  /// sample). Returns the encoder count (BLU) read at the start of the period, i.e. at the same
  /// instant the reference ref_blu belongs to (what a controller logs next to its reference).
  /// Throws gm::InputError when the loop has diverged (see kMaxPositionBlu).
  std::int64_t step(std::int64_t ref_blu);
  /// The message step() throws when the motor is at `position_blu` (relative to its start)
  /// after following `ref_blu`.
  static std::string divergence_message(double position_blu, std::int64_t ref_blu);

  /// One period T with the position loop open: the velocity loop follows v_ref_blu_s (BLU/s).
  /// For velocity step responses and diagnostics; do not mix with step() on the same object.
  void step_velocity(double v_ref_blu_s);

  double drive_command() const { return u_; }  ///< last drive command, drive units (V)
  double velocity_blu_s() const { return plant_.velocity_blu_s(); }  ///< motor velocity now
  bool saturated() const { return saturated_; }  ///< any servo sample of the last step saturated
  double motor_blu() const { return static_cast<double>(start_blu_) + plant_.position_blu(); }
  /// Table ("actual") position, BLU, continuous: the motor position minus the lost motion.
  /// Equal to motor_blu() when backlash_blu = 0. A DBB/linear scale would measure this.
  double table_blu() const {
    return static_cast<double>(start_blu_) + (modes_.count() > 0 ? modes_.output() : table_rel_);
  }
  /// The axis has structural modes (ServoBank then steps it as ServoAxis, not in lanes).
  bool has_modes() const { return modes_.count() > 0; }
  /// The position encoder is on the table (full-closed loop; ServoBank then steps it as ServoAxis).
  bool table_encoder() const { return table_encoder_; }
  /// The modes' deflection now: table (tool tip) minus the motor side after the lost motion, BLU
  /// (0 without modes).
  double deflection_blu() const { return modes_.count() > 0 ? modes_.output() - table_rel_ : 0.0; }
  double drive_limit() const { return u_max_; }  ///< saturation level of the drive command
  /// Everything step() changes, for ServoBank (the axes in SIMD lanes): it copies an axis's
  /// state out to its lanes and back when a sample must run here instead.
  struct Dynamic {
    DiscretePlant::State z;
    std::int64_t prev_count = 0, prev_ref = 0, prev_delta = 0;
    bool have_ref = false;
    double integ = 0.0, u = 0.0, table_rel = 0.0;
    bool saturated = false;
  };
  Dynamic dynamic() const {
    return {plant_.state(), prev_count_, prev_ref_,  prev_delta_, have_ref_,
            integ_,         u_,          table_rel_, saturated_};
  }
  void set_dynamic(const Dynamic& d) {
    plant_.set_state(d.z);
    prev_count_ = d.prev_count;
    prev_ref_ = d.prev_ref;
    prev_delta_ = d.prev_delta;
    have_ref_ = d.have_ref;
    integ_ = d.integ;
    u_ = d.u;
    table_rel_ = d.table_rel;
    saturated_ = d.saturated;
  }
  const DiscretePlant& plant() const { return plant_; }
  VelocityLoopForm form() const { return form_; }
  double kvp() const { return kvp_; }
  double kvi() const { return kvi_; }
  double kp() const { return kp_; }
  double kv_period_s() const { return kv_period_s_; }
  double kv_over_h() const { return kv_over_h_; }
  /// Feedforward gains on the reference's differences over T, in velocity-loop units (counts
  /// per kv_period_s) per BLU: ff1 kv_period_s / T on ref[k]-ref[k-1], ff2_s kv_period_s / T^2
  /// on its difference.
  double ff1_gain() const { return ff1_kv_; }
  double ff2_gain() const { return ff2_kv_; }
  double h_over_kv() const { return h_over_kv_; }
  double half_backlash_blu() const { return half_backlash_; }
  double coulomb_drive() const { return u_coulomb_; }
  double drive_N_per_unit() const { return n_per_unit_; }  ///< force per drive unit, N

 private:
  std::int64_t count_now() const;    ///< the position encoder's count now
  std::int64_t motor_count() const;  ///< the motor encoder's count now
  /// One servo period; `count` is the encoder count now (count_now(), passed in when the caller
  /// already has it).
  /// `ff`: the feedforward, counts per kv_period_s, added to the position loop's output.
  void servo_sample(std::int64_t count, double pos_ref_blu, double ff, bool position_loop,
                    double v_ref_blu_s);
  void plant_step(double u);

  DiscretePlant plant_;
  FlexibleModes modes_;
  VelocityLoopForm form_;
  double kvp_, kvi_, kp_;
  double h_s_, kv_period_s_;
  double kv_over_h_ = 1.0, h_over_kv_ = 1.0;  ///< kv_period_s / h and its inverse (divided once)
  double ff1_kv_ = 0.0, ff2_kv_ = 0.0;        ///< feedforward gains (ff1_gain(), ff2_gain())
  int substeps_;
  double u_max_ = 0.0, n_per_unit_ = 0.0, u_coulomb_ = 0.0, half_backlash_ = 0.0;
  std::int64_t start_blu_;
  std::int64_t prev_count_;
  std::int64_t prev_ref_;
  std::int64_t prev_delta_ =
      0;  ///< ref - prev_ref of the last step (the acceleration's difference)
  bool have_ref_ = false;
  double integ_ = 0.0;
  double u_ = 0.0;
  double table_rel_ = 0.0;
  bool saturated_ = false;
  bool table_encoder_ = false;
};

}  // namespace gm
