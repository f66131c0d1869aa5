// G38.2..G38.5 straight probing, simulated as LinuxCNC's standalone interpreter (rs274) does
// with no probe input: the probe feeds to its end point without tripping, stops there and backs
// off 0.254 mm (0.010 in) towards where it started; #5061-#5069 get that end point, #5070 = 0.
#include "interp/rotary_wrap.hpp"
#include "interp/steps.hpp"

namespace gm {

namespace {

constexpr double kProbeBackoffMm = 0.254;  // rs274 (saicanon.cc): 0.254 mm or 0.01 in

// The moves emitted from `first` on are LinuxCNC's STRAIGHT_PROBE.
void name_probe_moves(BlockCtx& ctx, std::size_t first) {
  for (std::size_t i = first; i < ctx.out.size(); ++i)
    if (auto* m = std::get_if<Motion>(&ctx.out[i])) m->canon = LineCanon::Probe;
}

}  // namespace

bool run_probe(BlockCtx& ctx, const Code& c) {
  const SourceLoc loc = ctx.w.word_of(Group::Motion) ? ctx.w.word_of(Group::Motion)->loc
                        : ctx.w.first_axis           ? ctx.w.first_axis->loc
                                                     : SourceLoc{ctx.block.line, 1};
  const std::string name = code_name(c);
  if (!comp_forbids(ctx, loc, "probe")) return false;
  if (!ctx.s.inverse_time && ctx.s.feed_mm_min <= 0.0)
    return ctx.fail(ErrorCode::ZeroFeed, loc, fmt::format("{} with zero feed rate", name));
  if (!check_feed(ctx, c.number10, loc)) return false;
  if (ctx.w.has_code('G', 530))
    return ctx.fail(ErrorCode::G53Misused, ctx.loc_of(Group::NonModal),
                    fmt::format("G53 with {}: G53 moves need G0 or G1", name));
  Pos9 target;
  if (!axis_target(ctx, ctx.s.position_mm, target)) return false;
  const Pos9 start = ctx.s.position_mm;
  const bool must_trip = c.number10 == 382 || c.number10 == 384;  // G38.3/G38.5 may miss
  if (must_trip && target == start)
    return ctx.fail(ErrorCode::ValueOutOfRange, loc,
                    fmt::format("{}: the start point is the probe point", name));
  const std::size_t first = ctx.out.size();
  if (!emit_straight(ctx, MotionKind::Line, target, loc)) return false;
  name_probe_moves(ctx, first);
  // The probe result, in the program's coordinates and units at this block.
  const Pos9 at = ctx.frame().to_program(target);
  for (int i = 0; i < kProgramAxes; ++i) {  // angles in degrees whatever the units
    const double v = axis_is_rotary(i) ? at[i] : at[i] / ctx.scale();
    ctx.results.add(5061 + i, axis_wraps(ctx.machine, i) ? wrap_360(v) : v);
  }
  ctx.results.add(5070, 0.0);  // not tripped
  const Eigen::Vector3d d = (start - target).head<3>();
  const double dist = d.norm();
  if (dist == 0.0) return true;
  Pos9 back = target;
  back.head<3>() += kProbeBackoffMm * d / dist;
  const std::size_t back_first = ctx.out.size();
  if (!emit_straight(ctx, MotionKind::Line, back, loc)) return false;
  name_probe_moves(ctx, back_first);
  return true;
}

}  // namespace gm
