// The steps that set modal state or emit events: comments, feed, plane, units, distance, path
// control, overrides, dwell and stops.
#include "common/units.hpp"
#include "interp/steps.hpp"

namespace gm {

bool run_nothing(BlockCtx&, const Code&) {
  return true;
}

bool step_comment(BlockCtx& ctx) {
  for (std::size_t i = 0; i < ctx.block.message_count; ++i)
    ctx.out.emplace_back(Event{ctx.block.line, EventKind::Message, ctx.block.messages[i].text});
  return true;
}

bool run_feed_mode(BlockCtx& ctx, const Code& c) {
  // LinuxCNC's convert_feed_mode: G94 and G95 set the feed to 0 (SET_FEED_RATE(0)) every time,
  // even in the mode already in force, so a G94 line needs an F before the next G1; G93 keeps it.
  if (c.number10 != 930) ctx.s.feed_mm_min = 0.0;
  ctx.s.inverse_time = c.number10 == 930;
  ctx.s.per_rev = c.number10 == 950;
  return true;
}

bool step_feed(BlockCtx& ctx) {
  if (!ctx.w.has('F')) return true;
  const auto* fw = ctx.w['F'];
  const double f = fw->value;
  if (f < 0) return ctx.fail(ErrorCode::NegativeFeed, fw->loc, fmt::format("F{:g} is negative", f));
  if (ctx.s.inverse_time)
    ctx.inverse_f = f;
  else
    ctx.s.feed_mm_min = f * ctx.scale();  // units before this block's G20/G21
  if (!within(ctx.s.feed_mm_min, kMaxFeedMmMin))
    return ctx.fail(ErrorCode::ValueOutOfRange, fw->loc,
                    fmt::format("F{:g} is {:g} mm/min, beyond {:g} mm/min", f, ctx.s.feed_mm_min,
                                kMaxFeedMmMin));
  return true;
}

bool run_override(BlockCtx& ctx, const Code& c) {
  EventKind k = c.number10 == 490 ? EventKind::OverrideDisable : EventKind::OverrideEnable;
  if (c.number10 == 500 && ctx.w.has('P')) {
    const double p = ctx.w['P']->value;
    if (p == 0.0)
      k = EventKind::OverrideDisable;
    else if (p != 1.0)
      return ctx.fail(ErrorCode::BadPWord, ctx.w['P']->loc,
                      fmt::format("M50 P{:g}: P must be 0 or 1", p));
  }
  if (!comp_forbids(ctx, ctx.loc_of(Group::MOverride), "change overrides")) return false;
  ctx.s.feed_override = k == EventKind::OverrideEnable;
  ctx.out.emplace_back(Event{ctx.block.line, k, {}});
  return true;
}

bool run_dwell(BlockCtx& ctx, const Code&) {
  if (!ctx.w.has('P'))
    return ctx.fail(ErrorCode::DwellWithoutP, ctx.loc_of(Group::NonModal),
                    "G4 without P (dwell seconds)");
  const double p = ctx.w['P']->value;
  if (p < 0)
    return ctx.fail(ErrorCode::NegativeDwell, ctx.w['P']->loc,
                    fmt::format("G4 P{:g}: negative dwell", p));
  emit_in_order(ctx, Dwell{ctx.block.line, p});
  return true;
}

bool run_plane(BlockCtx& ctx, const Code& c) {
  const Plane p = c.number10 == 170 ? Plane::XY : c.number10 == 180 ? Plane::XZ : Plane::YZ;
  if (p != ctx.s.plane && !comp_forbids(ctx, ctx.loc_of(Group::Plane), "change planes"))
    return false;
  ctx.s.plane = p;
  return true;
}

bool run_units(BlockCtx& ctx, const Code& c) {
  ctx.s.inch = c.number10 == 200;
  return true;
}

bool run_path_control(BlockCtx& ctx, const Code& c) {
  if (!comp_forbids(ctx, ctx.loc_of(Group::PathControl), "change the path control mode"))
    return false;
  // LinuxCNC: G61 = exact path, G61.1 = exact stop, G64 = continuous (P/Q ignored here).
  ctx.s.path_mode = c.number10 == 610   ? PathMode::ExactPath
                    : c.number10 == 611 ? PathMode::ExactStop
                                        : PathMode::Continuous;
  if (c.number10 == 640) {  // G64 P<path tolerance> Q<naive CAM tolerance>, program units (#21)
    for (char l : {'P', 'Q'})
      if (ctx.w.has(l) && !(ctx.w[l]->value >= 0.0))
        return ctx.fail(ErrorCode::ValueOutOfRange, ctx.w[l]->loc,
                        fmt::format("G64 {} must not be negative", l));
    const double u = ctx.s.mm_per_unit();
    ctx.s.path_tolerance_mm = ctx.w.has('P') ? ctx.w['P']->value * u : -1.0;
    ctx.s.naive_cam_tolerance_mm = ctx.w.has('Q') ? ctx.w['Q']->value * u : 0.0;
  }
  return true;
}

bool run_distance(BlockCtx& ctx, const Code& c) {
  ctx.s.incremental = c.number10 == 910;
  return true;
}

bool run_arc_distance(BlockCtx& ctx, const Code& c) {
  ctx.s.ijk_absolute = c.number10 == 901;
  return true;
}

// G7/G8: the mode only; the block's X word was already read as a diameter (Interpreter::execute).
bool run_lathe_mode(BlockCtx& ctx, const Code& c) {
  const bool diameter = c.number10 == 70;
  if (diameter != ctx.s.lathe_diameter) ctx.lathe_ijk_switch = diameter ? 0.5 : 2.0;
  ctx.s.lathe_diameter = diameter;
  return true;
}

bool run_stop(BlockCtx& ctx, const Code& c) {
  const EventKind k = c.number10 == 0 || c.number10 == 600 ? EventKind::Pause
                      : c.number10 == 10                   ? EventKind::OptionalPause
                                                           : EventKind::End;
  if (!comp_flush(ctx)) return false;  // the held-back move ends where the tool is
  if (k == EventKind::End) {           // LinuxCNC: spindle stopped, coolant off, then the end
    ctx.s.spindle_dir = 0;
    emit_io(ctx, EventKind::SpindleStop, 0, 0.0);
    if (ctx.s.mist) emit_io(ctx, EventKind::Mist, 0, 0.0);
    if (ctx.s.flood) emit_io(ctx, EventKind::Flood, 0, 0.0);
    ctx.s.mist = ctx.s.flood = false;
  }
  Event stop;
  stop.line = ctx.block.line;
  stop.kind = k;
  stop.index = c.number10 / 10;  // M0, M1, M2, M30, M60
  ctx.out.emplace_back(std::in_place_type<Event>, std::move(stop));
  // M0/M1/M60 hold the run for the machine's pause time (the operator presses resume).
  if (k != EventKind::End && ctx.machine.pause_s > 0.0)
    ctx.out.emplace_back(std::in_place_type<Dwell>,
                         Dwell{ctx.block.line, ctx.machine.pause_s, true});
  if (k == EventKind::End) {
    ctx.s.ended = true;
    ctx.s.comp.side = 0;  // M2/M30 turn compensation off (LinuxCNC)
    ctx.s.comp.first_move = true;
    select_coord_system(ctx.s, ctx.tables(), 0);  // and G54 (#5220 = 1 in the parameter file)
  }
  return true;
}

}  // namespace gm
