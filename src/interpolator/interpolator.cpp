// Sample-data interpolation with time carried across blocks, exact block ends, dwell, exact stop.
#include "interpolator/interpolator.hpp"

#include "common/rounding.hpp"
#include "common/units.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gm {

Interpolator::Interpolator(const InterpolatorConfig& cfg, CanonSource& source)
    : cfg_(cfg), source_(source), pos_mm_(cfg.start_mm) {
  started_.reserve(16);
  bool identity = true;
  for (int a = 0; a < cfg_.axes.count; ++a) identity = identity && cfg_.axes.program(a) == a;
  step_ = with_axis_count(cfg_.axes.count, [&](auto n) {
    constexpr int N = decltype(n)::value;
    return identity ? &Interpolator::step_n<N, true> : &Interpolator::step_n<N, false>;
  });
  span_ = with_axis_count(cfg_.axes.count, [&](auto n) {
    constexpr int N = decltype(n)::value;
    return identity ? &Interpolator::span_n<N, true> : &Interpolator::span_n<N, false>;
  });
}

double Interpolator::path_length_mm(const Motion& m) {
  return BlockGeometry::of(m).length_mm;
}

AxisVec Interpolator::position_on(const Motion& m, double s_mm) {
  const BlockGeometry g = BlockGeometry::of(m);
  return g.at_fraction(g.length_mm > 0.0 ? s_mm / g.length_mm : 1.0);
}

inline double Interpolator::block_speed_mm_s(const OverrideInput& ovr) const {
  const double scale = !override_enabled_ || synced_block_ ? 1.0
                       : rapid_block_                      ? ovr.rapid_scale
                                                           : ovr.feed_scale;
  // The tolerance planner's cap (src/planner/): the override acts before the Acc/Dec filter,
  // so no override may take the block faster than the speed its contour error was planned for.
  // G95 under G96: the spindle speeds up as the tool nears the axis, and the feed with it. A
  // spindle with a ramp feeds at the speed it has reached (G97).
  const double v100 =
      spindle_ramp_block_ ? units::mm_min_to_mm_s(block_.mm_per_rev * spindle_rpm_)
      : css_block_ ? units::mm_min_to_mm_s(block_.mm_per_rev * block_.spindle_rpm_at(pos_mm_[0]))
                   : speed_100_mm_s_;
  return std::min(v100 * scale, speed_cap_mm_s_);
}

bool Interpolator::pull_next() {
  while (!ended_) {
    if (!source_.next(scratch_)) {
      ended_ = true;
      break;
    }
    if (auto* m = std::get_if<Motion>(&scratch_)) {
      block_ = *m;
      const BlockGeometry* g = source_.geometry();  // the planner built it for a whole block
      geom_ = g != nullptr ? *g : BlockGeometry::of(block_);
      has_block_ = true;
      in_motion_ = true;
      s_mm_ = 0.0;
      line_ = block_.line;
      // The block's speed at 100 % (the same operations as before, per block instead of per
      // sample): the rapid rate, the G93 time's speed or the feed.
      rapid_block_ = block_.kind == MotionKind::Rapid;
      synced_block_ = block_.spindle_synced;  // G33: the feed override does not act
      css_block_ = block_.mm_per_rev > 0.0 && block_.css_surface_mm_min > 0.0;
      spindle_ramp_block_ = block_.mm_per_rev > 0.0 && cfg_.spindle_accel_rpm_s > 0.0;
      speed_100_mm_s_ = rapid_block_                  ? units::mm_min_to_mm_s(cfg_.rapid_mm_min)
                        : block_.inverse_time_s > 0.0 ? geom_.length_mm / block_.inverse_time_s
                                                      : units::mm_min_to_mm_s(block_.feed_mm_min);
      speed_cap_mm_s_ = block_.speed_cap_mm_s > 0.0 ? block_.speed_cap_mm_s
                                                    : std::numeric_limits<double>::infinity();
      override_ramp_mm_s_ = block_.override_ramp_mm_s;
      if (!(override_ramp_mm_s_ > 0.0)) override_ramping_ = false;
      comp_block_ = cfg_.arc_comp.enabled() && block_.kind == MotionKind::Arc &&
                    block_.comp_speed_mm_s > 0.0 && geom_.length_mm > 0.0;
      if (comp_block_) {
        // A piece of a cut arc after its first goes on with the arc's count and override.
        comp_from_mm_ = block_.comp_arc_length_mm > 0.0 ? block_.comp_arc_from_mm : 0.0;
        comp_length_mm_ =
            block_.comp_arc_length_mm > 0.0 ? block_.comp_arc_length_mm : geom_.length_mm;
        comp_exit_mm_s_ = block_.comp_exit_speed_mm_s;
        comp_blend_mm_ = cfg_.arc_comp.blend_length_mm(comp_length_mm_, block_.comp_speed_mm_s);
        comp_rows_ = cfg_.arc_comp.rows_weight(comp_length_mm_, block_.comp_speed_mm_s);
        comp_stops_ = block_.comp_stops_at_end;
        comp_private_ = block_.comp_private;
        if (comp_from_mm_ == 0.0) {
          comp_since_first_ = -1;
          comp_tail_scale_ = 0.0;
        }
        comp_rad_per_mm_ = std::abs(geom_.sweep_rad) / geom_.length_mm;
        comp_speed_step_ = cfg_.arc_comp.speed_step_mm_s(block_.comp_speed_mm_s);
        comp_cap_mm_s_ = std::min(speed_cap_mm_s_, block_.comp_speed_mm_s);
      }
      ++block_seq_;
      started_.push_back(block_);
      pending_events_ |= kEventBlockStart;
      return true;
    }
    if (auto* d = std::get_if<Dwell>(&scratch_)) {
      dwell_left_s_ = d->seconds;
      dwell_line_ = d->line;
      dwell_event_ = kEventDwell;
      line_ = d->line;
      if (dwell_left_s_ > 0.0) return true;
      continue;
    }
    const Event& e = std::get<Event>(scratch_);
    switch (e.kind) {
      case EventKind::Pause:
      case EventKind::OptionalPause:
        pending_events_ |= kEventPause;
        break;
      case EventKind::Message:
        pending_events_ |= kEventMessage;
        break;
      case EventKind::OverrideEnable:
        override_enabled_ = true;
        break;
      case EventKind::OverrideDisable:
        override_enabled_ = false;
        break;
      case EventKind::End:
        ended_ = true;
        break;
      case EventKind::WaitInput:
        // A simulation's inputs stay low: waiting for a rise, a fall or a high level runs to
        // the timeout Q (LinuxCNC's motion then gives #5399 = -1); low and immediate pass.
        if (e.mode >= 1 && e.mode <= 3 && e.value > 0.0) {
          dwell_left_s_ = e.value;
          dwell_line_ = e.line;
          line_ = e.line;
          dwell_event_ = kEventInputWait;
          return true;
        }
        break;
      case EventKind::SpindleSpeed:
        spindle_cmd_rpm_ = e.value;
        break;
      case EventKind::SpindleStart:
        spindle_on_ = true;
        break;
      case EventKind::SpindleStop:
        spindle_on_ = false;
        break;
      default:  // spindle, coolant, tools, I/O (motion/canon.hpp): no effect on the motion
        break;
    }
  }
  return false;
}

void Interpolator::apply_arc_comp(double v, double target) {
  const int a = geom_.ax.a, b = geom_.ax.b;
  const double da = pos_mm_[a] - geom_.center_mm[a], db = pos_mm_[b] - geom_.center_mm[b];
  const double r = std::sqrt(da * da + db * db);  // in the arc's plane, away from 0 and inf
  if (!(r > 0.0)) return;
  const double advance = v * cfg_.period_s;
  if (comp_since_first_ < 0) {
    comp_since_first_ = 0;
    comp_phase_in_ = (comp_from_mm_ + s_mm_) / advance;
  } else {
    ++comp_since_first_;
  }
  // x from the sample's in-plane angular rate; the end rows by its advances from the start and
  // to the end, of the whole arc.
  const double s_arc = comp_from_mm_ + s_mm_;
  const double to_end = cfg_.arc_comp.advances_to_end(comp_length_mm_ - s_arc, v, target,
                                                      comp_speed_step_, comp_cap_mm_s_);
  const ArcCompensation::Offset off = cfg_.arc_comp.offset(
      r, advance * comp_rad_per_mm_, comp_since_first_ + comp_phase_in_, to_end, comp_rows_,
      ArcCompensation::blend(s_arc, comp_length_mm_, comp_blend_mm_), comp_stops_, comp_private_,
      comp_private_);
  // Outward (da, db)/r; along the motion (−db, da)/r counter-clockwise, (db, −da)/r clockwise.
  const double along = geom_.sweep_rad > 0.0 ? off.along_mm : -off.along_mm;
  pos_mm_[a] += (off.radial_mm * da - along * db) / r;
  pos_mm_[b] += (off.radial_mm * db + along * da) / r;
}

template <int N, bool Identity>
InterpStatus Interpolator::step_n(const OverrideInput& ovr, CommandSample& out) {
  // The program axes the machine reads: 0..N-1 in program order, else any of the nine.
  constexpr int kComputedAxes = Identity ? std::max(N, 3) : kMaxAxes;
  if (finished_) return InterpStatus::Finished;
  std::uint32_t events = 0;
  double dt = cfg_.period_s;  // time of this sample still to spend
  // Rounding in the sums of times and lengths must not create an extra sample: a remainder
  // below these is nothing (1e-9 of a sample; 1e-9 mm, a millionth of a µm-BLU).
  const double dt_eps = 1e-9 * cfg_.period_s;
  constexpr double kLengthEps = 1e-9;
  bool moved_or_waited = false;
  double sample_speed = 0.0;  // the path speed of the last motion in this sample
  if (comp_tail_left_ > 0) --comp_tail_left_;

  // The spindle ramps towards its commanded speed, one sample's acceleration at a time.
  if (cfg_.spindle_accel_rpm_s > 0.0) {
    const double target = spindle_target_rpm(), step = cfg_.spindle_accel_rpm_s * cfg_.period_s;
    spindle_rpm_ = spindle_rpm_ < target ? std::min(target, spindle_rpm_ + step)
                                         : std::max(target, spindle_rpm_ - step);
  }
  if (settle_left_ > 0) {
    // Exact stop: the axes hold at the block end while the Acc/Dec output settles.
    --settle_left_;
    events |= kEventSettle;
    moved_or_waited = true;
    dt = 0.0;
  }
  while (dt > dt_eps) {
    if (dwell_left_s_ > 0.0) {
      events |= dwell_event_;
      line_ = dwell_line_;
      const double used = std::min(dt, dwell_left_s_);
      dwell_left_s_ -= used;
      if (dwell_left_s_ <= dt_eps) dwell_left_s_ = 0.0;
      dt -= used;
      moved_or_waited = true;
      continue;
    }
    if (!in_motion_) {
      if (!pull_next()) break;
      events |= pending_events_;
      pending_events_ = 0;
      continue;
    }
    // LinuxCNC waits for the spindle at speed before a synchronised move; a feed per
    // revolution waits while the spindle has not started turning (not a 0 % feed hold).
    if (spindle_ramp_block_ &&
        (block_.spindle_synced
             ? s_mm_ == 0.0 && std::abs(spindle_rpm_ - spindle_target_rpm()) > 1e-9
             : spindle_rpm_ <= 0.0)) {
      events |= kEventSpindleWait;
      moved_or_waited = true;
      break;
    }
    const double target = block_speed_mm_s(ovr);
    if (comp_block_ || comp_tail_left_ > 0)
      comp_tail_scale_ = std::max(comp_tail_scale_, ovr.feed_scale);
    const double v = comp_block_                 ? comp_ramped_speed(target)
                     : override_ramp_mm_s_ > 0.0 ? override_ramped_speed(target)
                     : comp_tail_left_ > 0       ? comp_tail_speed(target)
                                                 : target;
    sample_speed = v;
    if (!(v > 0.0)) {
      if (geom_.length_mm <= 0.0) {  // zero-length move: done, no time spent
        in_motion_ = false;
        continue;
      }
      events |= kEventHold;  // 0 % override: a feed hold, position stays
      moved_or_waited = true;
      break;
    }
    const double left = geom_.length_mm - s_mm_;
    if (v * dt < left - kLengthEps) {
      s_mm_ += v * dt;
      dt = 0.0;
      geom_.at_fraction_head<kComputedAxes>(s_mm_ / geom_.length_mm, pos_mm_);
      if (comp_block_) apply_arc_comp(v, target);
      moved_or_waited = true;
    } else {
      dt = std::max(0.0, dt - left / v);
      s_mm_ = geom_.length_mm;
      pos_mm_ = geom_.end_mm;  // the block end, exactly
      in_motion_ = false;
      moved_or_waited = true;
      if (comp_block_) {
        comp_tail_left_ = cfg_.arc_comp.ramp_samples();
        // A sample that ends on a cut inside the arc is commanded off it like any other.
        if (dt <= dt_eps && comp_from_mm_ + geom_.length_mm < comp_length_mm_)
          apply_arc_comp(v, target);
      }
      if (block_.path_mode != PathMode::Continuous) {
        // Exact stop (G61.1, G9) and exact path (G61) at a join that is not tangent (the planner
        // hands a G61 block with a tangent join on as continuous): with the Acc/Dec after
        // interpolation the path is followed exactly only if the filter drains at the block end,
        // so both drop the rest of this sample and hold while it does.
        settle_left_ = cfg_.settle_samples;
        break;
      }
    }
  }
  last_speed_mm_s_ = sample_speed;
  events |= pending_events_;
  pending_events_ = 0;
  if (!moved_or_waited && ended_ && !in_motion_ && dwell_left_s_ <= 0.0 && settle_left_ == 0) {
    finished_ = true;
    has_block_ = false;
    return InterpStatus::Finished;
  }
  // Machine axis a is program axis cfg_.axes.index[a].
  for (int a = 0; a < N; ++a)
    out.pos_blu[a] = round_half_away(
        pos_mm_[Identity ? a : cfg_.axes.index[static_cast<std::size_t>(a)]] / cfg_.blu_mm[a]);
  out.line = line_;
  out.block_seq = block_seq_;
  out.events = events;
  out.feed_scale = override_enabled_ && !synced_block_ ? ovr.feed_scale : 1.0;
  return InterpStatus::Working;
}

template <int N, bool Identity>
int Interpolator::span_n(const OverrideInput& ovr, int max, BluColumns& out, int row0,
                         CommandSample& last) {
  constexpr int kComputedAxes = Identity ? std::max(N, 3) : kMaxAxes;
  // What step_n does in a sample that starts and ends inside the current motion: nothing waits,
  // nothing is pulled, the speed does not depend on the position or on the spindle's ramp.
  if (finished_ || settle_left_ > 0 || dwell_left_s_ > 0.0 || !in_motion_ || pending_events_ != 0 ||
      spindle_ramp_block_ || css_block_ || comp_block_ || comp_tail_left_ > 0 ||
      override_ramp_mm_s_ > 0.0)
    return 0;
  if (cfg_.spindle_accel_rpm_s > 0.0 &&
      (spindle_rpm_ != spindle_target_rpm() || block_.css_surface_mm_min > 0.0))
    return 0;  // the spindle is still ramping (a change per sample)
  const double v = block_speed_mm_s(ovr);
  if (!(v > 0.0)) return 0;
  const double dt = cfg_.period_s;
  constexpr double kLengthEps = 1e-9;  // as step_n
  double blu_mm[N];
  int program_axis[N];
  for (int a = 0; a < N; ++a) {
    blu_mm[a] = cfg_.blu_mm[a];
    program_axis[a] = Identity ? a : cfg_.axes.index[static_cast<std::size_t>(a)];
  }
  int n = 0;
  if (geom_.kind == MotionKind::Arc) {
    for (; n < max; ++n) {
      if (!(v * dt < geom_.length_mm - s_mm_ - kLengthEps)) break;  // the block ends in it
      s_mm_ += v * dt;
      geom_.at_fraction_head<kComputedAxes>(s_mm_ / geom_.length_mm, pos_mm_);
      for (int a = 0; a < N; ++a)
        out.v[a][row0 + n] = round_half_away(pos_mm_[program_axis[a]] / blu_mm[a]);
    }
  } else {
    // Lines and rapids: the path lengths first (a running sum, as step_n adds them), then each
    // axis over the span at_fraction_head's way, start + u·(end − start), column by column.
    double s_at[kBlockSamples];
    const double L = geom_.length_mm;
    for (; n < max; ++n) {
      if (!(v * dt < L - s_mm_ - kLengthEps)) break;  // the block ends in this sample
      s_mm_ += v * dt;
      s_at[n] = s_mm_;
    }
    for (int a = 0; a < N; ++a) {
      const int pa = program_axis[a];
      const double p0 = geom_.start_mm[pa], p1 = geom_.end_mm[pa], d = p1 - p0, blu = blu_mm[a];
      std::int64_t* col = out.v[a] + row0;
      for (int i = 0; i < n; ++i) {
        const double u = s_at[i] / L;
        const double x = u >= 1.0 ? p1 : u <= 0.0 ? p0 : p0 + u * d;
        col[i] = round_half_away(x / blu);
      }
    }
    // The interpolator's position, as after the last sample.
    if (n > 0) geom_.at_fraction_head<kComputedAxes>(s_mm_ / L, pos_mm_);
  }
  if (n > 0) {
    last_speed_mm_s_ = v;
    for (int a = 0; a < N; ++a) last.pos_blu[a] = out.v[a][row0 + n - 1];
    last.line = line_;
    last.block_seq = block_seq_;
    last.events = 0;
    last.feed_scale = override_enabled_ && !synced_block_ ? ovr.feed_scale : 1.0;
  }
  return n;
}

}  // namespace gm
