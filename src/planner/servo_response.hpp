// The servo model's linear closed-loop response and the FIR + servo chain the planner plans for.
#pragma once

#include "accdec/taps.hpp"
#include "machine/machine.hpp"
#include "servo/servo_match.hpp"

#include <limits>
#include <vector>

namespace gm {

/// Table position at the start of periods k = 0..samples−1 (what the trace records as
/// table_blu) for a unit step of the position reference at k = 0, the axis at rest before.
/// ServoAxis without its nonlinear parts: no encoder rounding (the feedback reads the motor
/// position), no saturation, no friction, no lost motion. Everything else as ServoAxis::step:
/// substeps, linear extrapolation of the reference within T, P position loop with its velocity
/// and acceleration feedforward (ff1, ff2_s), PI/IP velocity loop on the backward difference,
/// the exact ZOH plant.
std::vector<double> servo_step_response(const AxisConfig& axis, double period_s, int substeps,
                                        int samples);

/// The drive command u of every servo sample (index k·substeps + j: sample j of period k) for a
/// unit step of the reference at k = 0, the linear servo of servo_step_response. It settles at
/// 0 (no force holds a position).
std::vector<double> servo_drive_step_response(const AxisConfig& axis, double period_s, int substeps,
                                              int samples);

/// The weights c_k of the whole linear chain from interpolator output to table position,
/// sampled at T: FIR weights h_i = b_i/b_s convolved with the servo's impulse response
/// (differences of servo_step_response), truncated at the first K with
/// T·Σ_{k≥K} |1 − S_k| ≤ tail_area_s (S the chain's step response), the tail lumped into the
/// last weight so that Σ c_k = 1 exactly. Truncating moves the output by at most V·tail_area_s
/// (Abel summation of the dropped tail against path increments ≤ V·T): the caller adds that to
/// its rounding margin. A step response that leaves [0, 1] by an area of at most clip_area_s
/// (the ringing a feedforward leaves, e.g.) is clipped into [0, 1], which moves the output by at
/// most V·clipped_s in the same way: the caller adds that too, and the planner then plans the
/// chain as one without overshoot.
struct ChainResponse {
  std::vector<double> weights;
  double tail_area_s = 0.0;   ///< T·Σ |1 − S_k| over the dropped tail (≤ the limit asked for)
  double overshoot_s = 0.0;   ///< T·Σ max(S_k − 1, 0): area of the step response above 1
  double undershoot_s = 0.0;  ///< T·Σ max(−S_k, 0): area below 0
  double clipped_s = 0.0;     ///< overshoot_s + undershoot_s when clipped away, else 0
};
ChainResponse chain_response(const Taps& taps, const AxisConfig& axis, double period_s,
                             int substeps, double tail_area_s, double clip_area_s = 0.0,
                             const MatchTaps* shaping = nullptr);

/// The X/Y/Z axis whose servo is closest to the others' (least servo_mismatch_s against it,
/// unmatched): the planned chain's servo. −1 without a linear axis.
int reference_servo_axis(const Machine& m);

/// T·Σ_k |S^a_k − S^ref_k| of each X/Y/Z servo `a` against axis `ref`'s (step responses of
/// servo_step_response, long enough to settle; S^a convolved with a's matching weights where
/// `match` has them), combined as a Euclidean norm over the axes, s. With FIR taps ≥ 0 summing
/// to 1 it bounds the same for the FIR + servo chains, so by Abel summation against path
/// increments ≤ V·T the table differs from the reference chain's output by at most V·(this)
/// whatever the path (docs/tolerance.md).
double servo_mismatch_s(const Machine& m, int ref, const std::vector<MatchTaps>* match = nullptr);
/// max_k |S^a_k − S^ref_k| of each servo `a` against `ref`, combined as servo_mismatch_s
/// (dimensionless). Against FIR output increments Δy_k (FIR taps ≥ 0, Σ = 1, so Σ|Δy| is at
/// most the command's Σ|Δx|), Abel summation bounds the table's difference by this times the
/// command's total variation: what a jump of the command costs, where servo_mismatch_s charges a
/// speed.
double servo_mismatch_peak(const Machine& m, int ref,
                           const std::vector<MatchTaps>* match = nullptr);

/// Servo matching (machine key servo_matching, on by default; only with tolerance_on = encoder
/// and the servo on, where X, Y and Z servos differ): every linear axis whose servo differs from
/// the reference axis's (reference_servo_axis) gets 32 matching taps f, Σ f = 1, fitted in least
/// squares so that its step response convolved with f is the reference's (ServoMatch filters
/// its command by the Acc/Dec taps and f together, rounded once as the filter's output is).
/// Kept for an axis only where they lower its mismatch. The pipeline and the planner design the
/// same taps.
struct ServoMatchDesign {
  int ref_axis = -1;            ///< the reference axis (−1: no matching)
  std::vector<MatchTaps> taps;  ///< the matched axes' taps (empty: none)
  bool shaped = false;          ///< every linear axis shaped (zero-phase-error taps)
};
ServoMatchDesign design_servo_match(const Machine& m, bool servo);

/// The fastest path speed V at which no X, Y or Z drive saturates whatever the path, mm/s: the
/// drive command is linear in the command's increments (|Δx| ≤ V·T on every axis) through the
/// Acc/Dec taps (with the axis's matching taps where `match` has them) and the servo
/// (servo_drive_step_response), so |u| ≤ V·T·max_j Σ_k |W^(j)_k|; V keeps that within the
/// drive's limit less its Coulomb friction. Infinity when no drive can saturate (or none can be
/// bounded: a drive weaker than its friction).
double drive_speed_limit_mm_s(const Machine& m, const std::vector<MatchTaps>* match = nullptr);

/// Σ_k |h_k − h_{k−1}| of `m`'s Acc/Dec weights h (h_{−1} = h_{N+1} = 0): what the filter
/// passes of a jump of its input at most, in total variation per unit (PlannerConfig::
/// fir_variation).
double fir_variation(const Machine& m);

/// The chain the planner plans against for `m`, and what it must add to it.
struct PlannedChain {
  /// The FIR alone (tolerance_on = acc_dec, or the servo off), or FIR + servo (tolerance_on =
  /// encoder): the chain_response of the reference axis (reference_servo_axis).
  std::vector<double> weights;
  /// The truncation allowance V_fastest·(tail_area + clipped): a chain whose step response
  /// leaves [0, 1] by at most half a BLU at V_fastest is clipped into it; one that overshoots
  /// more is planned with absolute moments (FilterMoments, docs/tolerance.md).
  double extra_margin_mm = 0.0;
  /// X, Y and Z servos that differ, as matched (design_servo_match): servo_mismatch_s (the
  /// planner keeps V·(that) of each tolerance, PlannerConfig::speed_error_s) and
  /// servo_mismatch_peak. 0: one servo for all, or no servo in the chain.
  double speed_error_s = 0.0;
  double step_error = 0.0;
  /// Encoder plans: drive_speed_limit_mm_s, the speed no drive saturates below (the chain is
  /// linear only there). Infinity otherwise.
  double drive_speed_mm_s = std::numeric_limits<double>::infinity();
};
PlannedChain plan_chain(const Machine& m, bool servo);

}  // namespace gm
