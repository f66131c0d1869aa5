// The sample-data interpolator (paper Fig. 1): every period T, each axis's integer position
// in BLU on the exact geometry, at feed × override; the increment per sample is V[k].
#pragma once

#include "common/axis.hpp"
#include "common/block_columns.hpp"
#include "interpolator/arc_compensation.hpp"
#include "motion/canon.hpp"
#include "motion/geometry.hpp"

#include <cstdint>
#include <vector>

namespace gm {

struct InterpolatorConfig {
  double period_s = 0.004;                          ///< T
  AxisLayout axes{};                                ///< the machine's axes (default X Y Z)
  MachineVec blu_mm = MachineVec::Constant(0.001);  ///< one count per machine axis, its order
  double rapid_mm_min = 6000;                       ///< G0 path speed at 100 % rapid override
  int settle_samples = 0;  ///< zero-velocity samples after an exact-stop block
  AxisVec start_mm = AxisVec::Zero();
  /// The spindle's acceleration, rpm/s (machine key spindle_accel_rpm_s); 0: it is at its
  /// commanded speed at once. With a ramp, feeds per revolution (G95) follow the speed it has
  /// reached and a synchronised move (G33, G76, G33.1) waits until it is at speed.
  double spindle_accel_rpm_s = 0.0;
  /// Pre-compensated arcs (Motion::comp_speed_mm_s > 0): the rule of the machine's Acc/Dec
  /// filter; off by default (such arcs are then commanded on their radius).
  ArcCompensation arc_comp{};
};

/// Overrides for one sample; 1.0 = 100 %. Ignored (taken as 1.0) while the program has
/// disabled override (M49, M50 P0).
struct OverrideInput {
  double feed_scale = 1.0;
  double rapid_scale = 1.0;
};

enum SampleEvent : std::uint32_t {
  kEventNone = 0,
  kEventPause = 1,         ///< M0/M1 passed in this sample
  kEventMessage = 2,       ///< (MSG, ...) passed in this sample
  kEventBlockStart = 4,    ///< a motion block started in this sample
  kEventDwell = 8,         ///< the sample is (partly) a dwell
  kEventHold = 16,         ///< the sample made no progress because the override is 0 %
  kEventSettle = 32,       ///< exact stop: the axes wait at a block end for the Acc/Dec to settle
  kEventSpindleWait = 64,  ///< a G33 move waits for the spindle to reach its speed
  kEventInputWait = 128,   ///< M66 waits for an input (a simulation's inputs stay low)
};

struct CommandSample {
  AxisBlu pos_blu = AxisBlu::Zero();  ///< commanded position after this sample
  int line = 0;                       ///< source line of the block the sample ends in
  std::uint64_t block_seq = 0;        ///< increments for each new Motion block
  std::uint32_t events = 0;           ///< SampleEvent bits
  double feed_scale = 1.0;            ///< the feed override in effect (1.0 if disabled)
};

enum class InterpStatus { Working, Finished };

/// Pulls canonical commands from a CanonSource as it needs them and produces one sample per
/// call. Time is what carries across blocks: a block that ends inside a sample hands the rest
/// of the sample's time to the next block, so the feed is exact across block boundaries and
/// every block end is the block's end point exactly. Nothing is allocated per sample.
class Interpolator {
 public:
  Interpolator(const InterpolatorConfig& cfg, CanonSource& source);

  /// Produces the next sample into `out`. Returns Finished (leaving `out` unchanged) once the
  /// program has ended (M2/M30 or the end of the stream) and the last motion has been output.
  InterpStatus step(const OverrideInput& ovr, CommandSample& out) {
    started_.clear();
    return (this->*step_)(ovr, out);
  }

  /// Produces up to `max` samples while only the position changes: the current motion keeps
  /// moving at one speed for the whole of each sample (no dwell, exact-stop wait, spindle-fed
  /// speed, block end or event), writing entries 0..N-1 of rows row0.. of `out` (the same
  /// arithmetic as step(), sample by sample; N is the machine's axis count). Returns the number
  /// of rows written; 0 when the next sample needs step(). Afterwards `last` holds what step()
  /// would have left in its CommandSample for the last row. started_motions() is empty.
  int span(const OverrideInput& ovr, int max, BluColumns& out, int row0, CommandSample& last) {
    started_.clear();
    return (this->*span_)(ovr, max, out, row0, last);
  }

  /// The motion blocks that became current during the last step(), in order: none or one in
  /// most samples, several when blocks are shorter than a sample's travel (CAM chords at speed).
  /// The last one is current_motion(). The list's memory is kept from sample to sample.
  const std::vector<Motion>& started_motions() const { return started_; }

  /// The motion block the last sample ended in (nullptr before the first and after the last).
  const Motion* current_motion() const { return has_block_ ? &block_ : nullptr; }

  /// Path length done in current_motion() after the last sample, mm: where on its path the
  /// sample was commanded (a pre-compensated arc's command lies off the path by its correction).
  double block_path_mm() const { return s_mm_; }

  /// Exact position at path length `s_mm` from the start of `m` (clamped to the block).
  static AxisVec position_on(const Motion& m, double s_mm);
  /// Path length of `m`, mm (helix: sqrt((R·θ)² + h²)).
  static double path_length_mm(const Motion& m);

 private:
  bool pull_next();  ///< loads the next motion or dwell; false at the end
  double block_speed_mm_s(const OverrideInput& ovr) const;
  /// step() for a machine of N axes; `Identity`: machine axis a is program axis a (XYZ, XYZA,
  /// ..., all nine), so only program axes 0..max(N, 3)-1 are computed. Writes entries 0..N-1
  /// of out.pos_blu (machine order; the rest untouched).
  template <int N, bool Identity>
  InterpStatus step_n(const OverrideInput& ovr, CommandSample& out);
  /// span() for a machine of N axes (Identity as for step_n).
  template <int N, bool Identity>
  int span_n(const OverrideInput& ovr, int max, BluColumns& out, int row0, CommandSample& last);

  InterpolatorConfig cfg_;
  CanonSource& source_;
  Canon scratch_;  ///< reused for every pull (no per-block allocation)
  /// step_n for the machine's axis count and layout, chosen once (with_axis_count).
  InterpStatus (Interpolator::*step_)(const OverrideInput&, CommandSample&) = nullptr;
  int (Interpolator::*span_)(const OverrideInput&, int, BluColumns&, int, CommandSample&) = nullptr;

  Motion block_{};
  std::vector<Motion> started_;  ///< blocks loaded during the current step()
  BlockGeometry geom_{};
  bool has_block_ = false;     ///< a motion block is loaded (possibly finished)
  bool in_motion_ = false;     ///< the loaded block still has distance to go
  bool rapid_block_ = false;   ///< the loaded block is a rapid (the rapid override applies)
  bool synced_block_ = false;  ///< the loaded block is spindle-synchronised (G33: no override)
  bool css_block_ = false;     ///< fed per revolution under G96: the speed follows the radius
  // The spindle (from the spindle events), for feeds per revolution when it has a ramp.
  double spindle_cmd_rpm_ = 0.0;     ///< the last S
  bool spindle_on_ = false;          ///< M3/M4 .. M5
  double spindle_rpm_ = 0.0;         ///< the speed it has reached
  bool spindle_ramp_block_ = false;  ///< the loaded block is fed by a spindle with a ramp
  /// What the spindle is ramping towards: S, or under G96 (the last block's surface speed) the
  /// speed for the tool's radius now, at most D (LinuxCNC motion's CSS rule).
  double spindle_target_rpm() const {
    if (!spindle_on_) return 0.0;
    return has_block_ && block_.css_surface_mm_min > 0.0 ? block_.spindle_rpm_at(pos_mm_[0])
                                                         : spindle_cmd_rpm_;
  }
  double speed_100_mm_s_ = 0.0;  ///< its speed at 100 % override
  double speed_cap_mm_s_ = 0.0;  ///< the planner's cap (infinity: none)
  // A pre-compensated arc (arc_compensation.hpp): commanded on R + c with its end rows, its
  // speed ramped.
  bool comp_block_ = false;
  double comp_blend_mm_ = 0.0;    ///< the radial blend's length at each end
  double comp_rows_ = 0.0;        ///< the end rows' weight against the blend (rows_weight)
  bool comp_stops_ = false;       ///< the arc's command stops on its end point
  bool comp_private_ = false;     ///< its moving ends take the distance rows (Motion::comp_private)
  int comp_since_first_ = -1;     ///< samples on the arc since its first (−1: none yet)
  double comp_phase_in_ = 0.0;    ///< how far past the start the first lay, of its advance
  double comp_rad_per_mm_ = 0.0;  ///< in-plane angle per path length, |sweep| / L
  double comp_speed_step_ = 0.0;  ///< largest speed change per sample, mm/s
  /// The arc's speed limit: the planner's cap and v_p, the speed it was planned for (the
  /// planner's check caps it there: a faster block before it steps down at once, not by the
  /// ramp).
  double comp_cap_mm_s_ = 0.0;
  /// A piece of a cut arc (Motion::comp_arc_from_mm): where the block starts in the whole arc,
  /// the whole arc's length (the block's own when it is whole), and the speed to be down to at
  /// the block's end (0: none).
  double comp_from_mm_ = 0.0;
  double comp_length_mm_ = 0.0;
  double comp_exit_mm_s_ = 0.0;
  double last_speed_mm_s_ = 0.0;  ///< path speed of the last sample (0 after a stop)
  /// The speed of a compensated arc's sample: `target` by ArcCompensation::next_speed, and no
  /// faster than the ramp can brake from to the block's exit speed.
  double comp_ramped_speed(double target) const {
    if (comp_exit_mm_s_ > 0.0)
      target = std::min(target, cfg_.arc_comp.braking_speed(geom_.length_mm - s_mm_,
                                                            comp_exit_mm_s_, comp_speed_step_));
    return cfg_.arc_comp.next_speed(last_speed_mm_s_, target, comp_speed_step_, comp_cap_mm_s_,
                                    comp_length_mm_ - comp_from_mm_ - s_mm_);
  }
  // The window after a compensated arc: the filter still holds the arc's samples, whose end rows
  // were commanded for a path that goes on (or stops where the planner said), so a fall of the
  // override there (a feed hold) takes the arc's ramp instead of stopping the command at once.
  int comp_tail_left_ = 0;        ///< samples until the window has left the last such arc
  double comp_tail_scale_ = 0.0;  ///< the highest feed override since that arc began
  /// A feed block's speed in that window: `target`, but falling from the last sample's speed
  /// by at most the arc's step while the override is below the highest of the window (a fall
  /// the program or the planner asks for, a lower feed or cap, is taken at once as elsewhere).
  double comp_tail_speed(double target) const {
    if (rapid_block_ || synced_block_ || css_block_ || spindle_ramp_block_ || !override_enabled_)
      return target;
    const double slowest = std::min(last_speed_mm_s_ - comp_speed_step_,
                                    std::min(speed_cap_mm_s_, speed_100_mm_s_ * comp_tail_scale_));
    return std::max(target, slowest);
  }
  /// A line before a private arc (Motion::override_ramp_mm_s): a fall of the speed below the
  /// block's cap (the override's: the planner caps such lines at the arc's speed) takes at most
  /// that step a sample, as the arc's ramp does, and so does the rise back after it (the arc's
  /// rows for the distance are fitted for such speeds); a fall to the cap, and a rise the
  /// program or the plan asks for, at once.
  double override_ramp_mm_s_ = 0.0;
  bool override_ramping_ = false;  ///< a fall was ramped: the rise back is ramped too
  double override_ramped_speed(double target) {
    if (rapid_block_ || synced_block_ || css_block_ || spindle_ramp_block_) return target;
    const double step = override_ramp_mm_s_, last = last_speed_mm_s_;
    if (target < last) {
      const double v = std::max(target, std::min(last - step, speed_cap_mm_s_));
      if (v < speed_cap_mm_s_) override_ramping_ = true;
      return v;
    }
    if (!override_ramping_) return target;
    const double v = std::min(target, last + step);
    if (v == target) override_ramping_ = false;
    return v;
  }
  /// Moves pos_mm_ (on the arc at s_mm_) by the correction for speed v, radial and (at the
  /// arc's ends) along the path; `target` the speed the arc's ramp is heading for.
  void apply_arc_comp(double v, double target);
  double s_mm_ = 0.0;          ///< path length done in the current block
  double dwell_left_s_ = 0.0;  ///< remaining dwell time
  int dwell_line_ = 0;
  std::uint32_t dwell_event_ = kEventDwell;  ///< what the wait is: a dwell or an M66 wait
  int settle_left_ = 0;                      ///< exact-stop hold samples still to emit
  bool override_enabled_ = true;
  bool ended_ = false;  ///< End seen or the stream ran out
  bool finished_ = false;
  std::uint64_t block_seq_ = 0;
  std::uint32_t pending_events_ = 0;  ///< events met while pulling, reported with the next sample
  int line_ = 0;
  AxisVec pos_mm_;
};

}  // namespace gm
