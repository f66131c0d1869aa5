// The tolerance planner's check of a pre-compensated arc: the filter output of the arc alone,
// between its tangent lines, commanded as the interpolator commands it, simulated.
#pragma once

#include "interpolator/arc_compensation.hpp"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <limits>
#include <vector>

namespace gm {

/// Why the arc alone: the filter is linear and the path's tangent u(s) is a sum of one term per
/// element (an arc contributes u(σ) − u(start) inside it and u(end) − u(start) after it, a corner
/// a step), so y − x(s̄) = Σ h_i (x(s_i) − x(s̄)) + Σ h_i c_i n_i is the sum over the elements of
/// what each does between its tangent lines, rotated (docs/tolerance.md, "Pre-compensated
/// arcs"). The planner's sharing then adds the elements' bounds as before; this class gives the
/// compensated arc's term: the largest |y − x(s̄)| of the isolated arc, simulated in double
/// precision through the weights (rounding is the planner's margin).
class ArcPrecompCheck {
 public:
  /// The weights h_i (Σ = 1: the FIR's, or the FIR and servo chain's) at period T; enabled() is
  /// false where ArcCompensation's is.
  /// `line_ratio` > 0: the lines beside the arc may run up to line_ratio·v_p (the planner caps
  /// them there, not at v_p), and error_mm also simulates the speed steps at the arc's ends
  /// (stepped_mm at that ratio); 0: the lines run at the arc's speed (constant-speed runs only).
  /// `near_s`: the lines are at most v_p over near_s·v_p of path beside the arc, and at most
  /// line_ratio·v_p only beyond (0: the step at the arc's ends).
  /// `end_rows`: as ArcCompensation's.
  ArcPrecompCheck(const std::vector<double>& weights, double period_s, double line_ratio = 0.0,
                  double near_s = 0.0, bool end_rows = true);

  bool enabled() const { return rule_.enabled(); }
  /// How the check commands and judges an arc. Shared: the end rows fitted for |y − x(s̄)|,
  /// judged so (what adds up over a path's elements: the planner's sharing). Private: an arc
  /// whose windows hold nothing else (the tolerance planner's arc_privacy: no other element
  /// within its reach but near-tangent corners): its moving ends take the rows fitted for the
  /// distance (ArcEndRows::Way::MovingDistance) and every output is judged by its distance from
  /// the path (the line before, the arc, the line after); in such a window the output's error
  /// is the arc's alone and the path near it the simulated one. PrivateDrift: the same command
  /// judged by |y − x(s̄)|, which bounds what a near-tangent corner beside a private arc turns
  /// into distance (docs/tolerance-arc-ends.md, "Private arcs").
  enum class Judging { Shared, Private, PrivateDrift };
  /// While one lives, the check judges as `how`.
  class Judged {
   public:
    Judged(const ArcPrecompCheck& check, Judging how) : check_(check), was_(check.judging_) {
      check_.judging_ = how;
    }
    Judged(const Judged&) = delete;
    Judged& operator=(const Judged&) = delete;
    ~Judged() { check_.judging_ = was_; }

   private:
    const ArcPrecompCheck& check_;
    Judging was_;
  };
  Judging judging() const { return judging_; }
  /// The lines' speed beside an arc planned at v_p is at most line_ratio()·v_p (0: v_p).
  double line_ratio() const { return line_ratio_; }
  /// ... but at most v_p over near_s()·v_p of path next to the arc.
  double near_s() const { return near_s_; }
  const ArcCompensation& rule() const { return rule_; }
  /// Samples in the filter's window (N + 1 weights).
  std::size_t window_samples() const { return h_.size(); }
  /// Largest path speed at which an arc of `sweep_abs_rad` over `length_mm` of path may be
  /// compensated: A(ωT) >= ArcCompensation::kMinGain with ω = v·|θ|/L.
  double speed_limit_mm_s(double sweep_abs_rad, double length_mm) const;
  /// Largest path speed up to speed_limit_mm_s at which the compensated command's steady speed
  /// v/A(ωT) stays within `command_mm_s` (a drive's speed limit: the command, not the path,
  /// moves the drive).
  double command_limit_mm_s(double sweep_abs_rad, double length_mm, double command_mm_s) const;
  /// The term of an arc of radius r, |θ| and path length L planned at v_p (the interpolator's
  /// blend and ramp for v_p): the largest of the isolated arc at constant speeds v_p and 0.6·v_p
  /// (with line_ratio() > 0 also with the lines beside it at line_ratio() times those speeds,
  /// stepped_mm), plus the transient of the ramp from v_p to rest and back on the steady arc. mm.
  double error_mm(double radius_mm, double sweep_abs_rad, double length_mm, double v_plan) const;
  /// error_mm without the ramp's transient: the largest of the isolated arc at v_p and 0.6·v_p
  /// (stepped too when line_ratio() > 0; and 0), so that error_mm == isolated_worst_mm +
  /// ramp_mm bit for bit.
  double isolated_worst_mm(double radius_mm, double sweep_abs_rad, double length_mm,
                           double v_plan) const;
  /// Exactly `error_mm(...) * scale <= share` (scale > 0), sooner: a simulation stops as soon as
  /// what it has found already exceeds (the sum and product are monotone in the rounding), and
  /// the terms of an arc already simulated at the same radius, sweep, length and speed are
  /// taken from a cache (a repeated feature, or the same arc planned again beside claims).
  bool error_within(double radius_mm, double sweep_abs_rad, double length_mm, double v_plan,
                    double scale, double share) const;
  /// The isolated arc at speed `v` (path): between moving tangent lines, starting from rest
  /// (the interpolator's ramp) and stopping on its end point; the first sample `phase` of a
  /// sample past a window before the arc: the largest |y − x(s̄)|, mm.
  double isolated_mm(double radius_mm, double sweep_abs_rad, double length_mm, double v_plan,
                     double v, double phase) const;
  /// The isolated arc with speed steps at its ends, by the interpolator's rules: the lines before
  /// and after it at path speed `v_line`, the arc at target `v` (at most v_p), its speed ramped
  /// from the line's by the rule's step and capped at v_p; moving through both ends, stopping
  /// on its end point after the line, and starting from rest into the line after; the first
  /// sample `phase` of a sample into the line before the arc: the largest |y − x(s̄)|, mm.
  double stepped_mm(double radius_mm, double sweep_abs_rad, double length_mm, double v_plan,
                    double v, double v_line, double phase) const;
  /// A near circle's extra term (docs/tolerance.md, "Near circles"): an arc whose radius runs
  /// linearly from r0 to r1 over its sweep, as the interpolator moves it (a CAM program's arcs
  /// rounded to a few decimals), against the circle of the same sweep and path length L, whose
  /// term is at most `circle_mm`, both planned at v_p. At equal path length the near circle is
  /// that circle, turned by its constant angle to the radius, moved radially by δ(s), linear in
  /// s, |δ| <= Δr/2, and its command's offset is the circle's scaled by r(s)/(L/|θ|) (the rate
  /// x is the arc's, the same). With M = v_p·T·spread >= Σ h_i|s_i − s̄| (spread =
  /// Σ_ij |h_i||h_j||i − j|, samples at speeds up to v_p), r = r_min, U = v_p²σ²/(2r) the
  /// uncompensated arc's term and c·K the largest offset (largest_offset_factor):
  /// Δr·(M/(2r) + M/L + (circle_mm + U)/(2r) + M·c·K/(L·r)), mm. Checked against the real
  /// interpolator and FIR on near circles (test_arc_precomp.cpp).
  double spiral_mm(double r_min, double r_max, double sweep_abs_rad, double length_mm,
                   double v_plan, double circle_mm) const;
  /// What a servo mismatch (M = servo_mismatch_s, E = servo_mismatch_peak) moves the table by
  /// from the command's offset (ArcCompensation::offset) on an arc planned at v_p, at speeds up
  /// to v_p, mm. The path's own part, M·v, is the planner's MismatchReserve. Abel summation
  /// against the filter output's increments splits the offset o = s + p:
  ///  * the steady offset s = c·n turning by x and changing with c (the ramp's largest
  ///    c(v) − c(v − step)) on every sample: M/T times it;
  ///  * the ends' deviation p from it: the blend's, from 0 to c and back, E times that total
  ///    variation; the rows', whose jumps the filter smooths, E·fir_variation·Σ|p| (Δ(h ∗ p) =
  ///    (Δh) ∗ p; fir_variation = Σ|h_k − h_{k−1}|, 0: infinite).
  /// Mixed rows and blend (rows_weight) in proportion.
  double offset_mismatch_mm(double radius_mm, double sweep_abs_rad, double length_mm, double v_plan,
                            double speed_error_s, double step_error, double fir_variation) const;
  /// At least offset_mismatch_mm, cheaply: |c| and its steps at most r times the table's
  /// largest |1/A − 1| up to the arc's rate (correction_ratio_cap), the offset factor K at most
  /// its largest at the rows' rate knots up to the one past that rate (K is convex between
  /// knots, the shapes being linear in the rate there).
  double offset_mismatch_cap_mm(double radius_mm, double sweep_abs_rad, double length_mm,
                                double v_plan, double speed_error_s, double step_error,
                                double fir_variation) const;
  /// The ramp's transient on the steady arc, mm.
  double ramp_mm(double radius_mm, double sweep_abs_rad, double length_mm, double v_plan) const;
  /// The largest transient of ramps from v_p down to f·v_p and back on the steady arc, f in
  /// kRampFloors, held a window at f·v_p or turning at once, twice (reversals_mm): a ramp
  /// shorter than the window has its start and end in one window (where ramp_mm's, from v_p to
  /// rest, are a window apart), and a reversal doubles the change of acceleration, mm. The
  /// whole error of a window on the steady arc away from its ends (the planner's middle of a
  /// chain: slower_ends).
  double ramps_mm(double radius_mm, double sweep_abs_rad, double length_mm, double v_plan) const;
  static constexpr std::array<double, 6> kRampFloors{0.0, 0.2, 0.4, 0.6, 0.8, 0.9};
  /// isolated_mm with each of its runs simulated whole (two of them are paired in isolated_mm,
  /// one forked from the other where they part): the reference isolated_mm must equal exactly.
  double isolated_unpaired_mm(double radius_mm, double sweep_abs_rad, double length_mm,
                              double v_plan, double v, double phase) const;

 private:
  enum class Start { Moving, FromRest };  ///< at speed on the line before, or from rest
  /// On along the line after, stopping at the end, or both (the larger of the two: they are
  /// the same run until the command reaches the end, simulated once up to there).
  enum class End { Moving, Stop, Both };
  /// The filter over in-plane path [p_from, p_to] (samples every vp·T from p_from + phase·vp·T;
  /// from rest: a window at the start, then the ramp), the largest |y − x(s̄)| once the window
  /// is full.
  double run_segment(double p_from, double p_to, double phase, Start start, End end) const;
  /// From v_p down to floor·v_p and up, twice, turning at once, mm.
  double reversals_mm(double radius_mm, double sweep_abs_rad, double length_mm, double v_plan,
                      double floor) const;
  /// The filter over the steady arc (its correction at each sample's speed) from v_start, the
  /// speed of sample k set by next_speed(k, v) (false: the run is over): the largest
  /// |y − x(s̄)| once the window is full, mm.
  template <class Profile>
  double steady_arc_mm(double radius_mm, double sweep_abs_rad, double length_mm, double v_start,
                       Profile next_speed) const;
  /// ramp_mm's run with the ramp down to floor·v_p instead of rest.
  double ramp_to_mm(double radius_mm, double sweep_abs_rad, double length_mm, double v_plan,
                    double floor) const;
  /// One run's state between samples.
  /// `since_first`, `phase_in`: the interpolator's count and phase for the end rows.
  /// `pending`: the newest samples' outputs not yet judged (push_sample judges kBatch at once,
  /// flush the rest).
  struct SimState {
    double p = 0, v = 0, worst = 0, worst2 = 0, phase_in = 0;  ///< worst2: the worst's square
    std::size_t rest = 0, count = 0, head = 0;
    int since_first = -1;
    std::size_t pending = 0;
  };
  /// Advances the command by one sample (s.v: its speed).
  void advance(SimState& s) const;
  /// The command at s.p (on the arc: its correction and end rows at speed s.v) into the window;
  /// once it is full, the output's distance.
  void push_sample(SimState& s) const;
  /// One run of stepped_mm: from in-plane p_start (< 0: on the line before, at the line's
  /// speed; >= 0: on the arc at speed v; FromRest: at rest on the arc's start), until the
  /// window has left the arc (moving), n samples on the end point (stop) or p_until.
  double run_stepped(double p_start, double p_until, Start start, bool stop) const;
  double stepped_runs(double phase) const;  ///< stepped_mm's runs on the arc set_arc set
  /// isolated_mm's runs; `paired`: Moving and Stop runs that share a start as one End::Both.
  double isolated_runs(double v, double phase, bool paired) const;
  /// Sets the arc isolated_mm simulates.
  void set_arc(double radius_mm, double sweep_abs_rad, double length_mm, double v_plan,
               double v) const;
  Eigen::Vector2d point(double p) const;  ///< the isolated path at in-plane length p
  /// A sample into the window: the slot before `head` becomes the newest (head).
  void put(std::size_t& head, const Eigen::Vector2d& x, double p) const;
  /// The filter output y and p̄ = Σ h_i p_i of the window whose newest sample is at ring slot
  /// `head`.
  void window_output(std::size_t head, Eigen::Vector2d& y, double& pbar) const;
  static constexpr std::size_t kBatch = 4;  ///< outputs computed together (batch_outputs)
  /// Ring slots: the window and the kBatch − 1 samples before it.
  std::size_t ring_slots() const { return h_.size() + kBatch - 1; }
  /// window_output at head + j for j = 0..kBatch − 1 (the newest first), each bit for bit, in
  /// one pass.
  void batch_outputs(std::size_t head, std::array<Eigen::Vector2d, kBatch>& y,
                     std::array<double, kBatch>& pbar) const;
  /// The output's distance from the path into s.worst (and the early stop).
  void judge(SimState& s, const Eigen::Vector2d& y, double pbar) const;
  /// The moving ends take the rows fitted for the distance (Private, PrivateDrift).
  bool distance_rows() const { return judging_ != Judging::Shared; }
  /// The distance of y from the isolated path (the line before, the arc, the line after; from
  /// rest without the line before, stopping without the line after: a full stop may turn there).
  double path_distance(const Eigen::Vector2d& y) const;
  /// Judges the pending outputs, if any.
  void flush(SimState& s) const;

  std::vector<double> h_;
  bool nonnegative_ = false;  ///< every h_i >= 0
  double spread_ = 0.0;       ///< Σ_ij |h_i||h_j||i − j|, samples (spiral_mm)
  double variance_s2_ = 0.0;  ///< σ² of the weights' time, s² (spiral_mm)
  double period_s_;
  bool use_avx2_ = false;  ///< batch_outputs' kernel (active_isa())
  ArcCompensation rule_;
  // The isolated arc being simulated (set by isolated_mm): radius, in-plane length, q = r·|θ|/L,
  // the radial blend's length (path) and the end rows' weight against it, the path the ends
  // cover (at most L/2), in-plane step per sample.
  mutable double r_ = 0, lp_ = 0, q_ = 0, len_ = 0, blend_ = 0, rows_ = 0, end_len_ = 0, dp_ = 0,
                 v_ = 0, dv_ = 0;
  /// The end's direction (sin, cos of lp_/r_) and point, for point() past the arc (set_arc).
  mutable double end_sin_ = 0, end_cos_ = 1, end_sin_r_ = 0, end_1mcos_r_ = 0;
  mutable bool stops_ = false;  ///< the run stops on the arc's end point: its end rows for a stop
  mutable Judging judging_ = Judging::Shared;  ///< Judged
  mutable bool rest_start_ = false;  ///< run_segment's run starts from rest (path_distance)
  /// stepped_mm: the arc's cap, the lines' speed and the in-plane stretch beside the arc at v.
  mutable double vplan_ = 0, vline_ = 0, near_p_ = 0;
  double line_ratio_ = 0.0, near_s_ = 0.0;
  /// The window and the kBatch − 1 samples before it (ring_slots()), each slot stored twice
  /// (at k and k + ring_slots()) so that a window lies in a row; the newest at a moving head.
  mutable std::vector<Eigen::Vector2d> ring_, fork_ring_;
  mutable std::vector<double> ring_p_, fork_ring_p_;
  /// error_within's early stop: a run ends once (its worst + stop_add_)·stop_scale_ > stop_share_
  /// (never when stop_share_ is infinite), and sets stopped_.
  mutable double stop_add_ = 0, stop_scale_ = 1,
                 stop_share_ = std::numeric_limits<double>::infinity();
  mutable bool stopped_ = false;
  bool over(double worst) const { return (worst + stop_add_) * stop_scale_ > stop_share_; }
  /// error_within's cache, direct-mapped (no allocation after construction): the arc's key, its
  /// ramp term, and the isolated term, exact or (not `exact`) a lower bound where a run stopped.
  struct Cached {
    double r = -1, sweep = 0, len = 0, v = 0, ramp = 0, iso = 0;
    bool exact = false;
    Judging judging = Judging::Shared;
  };
  mutable std::vector<Cached> cache_;
  /// largest_offset_factor at each rate knot (NaN: not yet computed): offset_mismatch_cap_mm.
  /// (The shared rows', then the distance's: distance_rows().)
  mutable std::array<std::array<double, ArcEndRows::kRateKnots.size()>, 2> knot_factor_{};
};

}  // namespace gm
