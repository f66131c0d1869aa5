// The motion steps: G0/G1 straight moves and G2/G3 arcs and helices, in machine coordinates.
#include "common/units.hpp"
#include "interp/arc.hpp"
#include "interp/rotary_wrap.hpp"
#include "interp/steps.hpp"

#include <algorithm>
#include <bit>
#include <numbers>

namespace gm {

namespace {

const char* plane_text(Plane p) {
  return p == Plane::XY ? "XY plane (G17)" : p == Plane::XZ ? "XZ plane (G18)" : "YZ plane (G19)";
}

// Where a motion error is reported: the motion code, else the first axis word, else the block.
SourceLoc motion_loc(const BlockCtx& ctx) {
  if (const auto* mw = ctx.w.word_of(Group::Motion)) return mw->loc;
  if (ctx.w.first_axis) return ctx.w.first_axis->loc;
  return SourceLoc{ctx.block.line, 1};
}

PathMode block_path_mode(const BlockCtx& ctx) {
  return ctx.w.in(Group::ExactStop) ? PathMode::ExactStop : ctx.s.path_mode;
}

// Path mode and, under G64, the contour tolerance in force (G64 P, else the machine's; #21).
// G9 stops this block's end only: the G64 in force still holds along its path (an arc's
// shrink), so the block keeps the tolerance.
void set_path_mode(const BlockCtx& ctx, Motion& mo) {
  mo.path_mode = block_path_mode(ctx);
  if (ctx.s.path_mode != PathMode::Continuous) return;
  mo.path_tolerance_mm =
      ctx.s.path_tolerance_mm >= 0.0 ? ctx.s.path_tolerance_mm : ctx.machine.path_tolerance_mm;
  mo.naive_cam_tolerance_mm = ctx.s.naive_cam_tolerance_mm;
}

// Feed of a feed move (G94 modal feed, or G93: LinuxCNC interp_inverse.cc,
// rate = MAX(0.1, length x F) in program units/min).
bool set_feed(BlockCtx& ctx, Motion& mo) {
  if (ctx.s.per_rev) {
    set_spindle_feed(ctx, mo, ctx.s.feed_mm_min);
    return true;
  }
  if (!ctx.s.inverse_time) {
    mo.feed_mm_min = ctx.s.feed_mm_min;
    return true;
  }
  const double length_mm = motion_length_mm(mo);
  if (!inverse_time_feed(ctx, length_mm, mo.feed_mm_min)) return false;
  mo.inverse_time_s = units::kSecondsPerMinute * length_mm / mo.feed_mm_min;
  return true;
}

}  // namespace

bool inverse_time_feed(BlockCtx& ctx, double length_mm, double& feed_mm_min) {
  feed_mm_min = std::max(0.1 * ctx.scale(), length_mm * ctx.inverse_f);
  if (within(feed_mm_min, kMaxFeedMmMin)) return true;
  return ctx.fail(ErrorCode::ValueOutOfRange, ctx.w['F']->loc,
                  fmt::format("G93 F{:g} over {:g} mm is {:g} mm/min, beyond {:g} mm/min",
                              ctx.inverse_f, length_mm, feed_mm_min, kMaxFeedMmMin));
}

void set_spindle_feed(const BlockCtx& ctx, Motion& mo, double mm_per_rev) {
  const ModalState& s = ctx.s;
  mo.mm_per_rev = mm_per_rev;
  mo.spindle_rpm = s.spindle_rpm;
  mo.css_surface_mm_min = s.css ? s.css_surface_mm_min : 0.0;
  mo.css_max_rpm = s.css ? s.css_max_rpm : 0.0;
  mo.css_axis_x_mm = ctx.offset()[0];
  mo.feed_mm_min = mm_per_rev * mo.spindle_rpm_at(mo.start_mm[0]);
}

bool check_feed(BlockCtx& ctx, int code10, SourceLoc loc) {
  auto name = [code10] { return code_name('G', code10); };
  if (ctx.s.per_rev) {
    // rs274: zero F, zero S ("Cannot feed with zero spindle speed in feed per rev mode"); a
    // stopped spindle rs274 lets through, but the move would never end, so it is refused here.
    if (ctx.s.feed_mm_min <= 0.0)
      return ctx.fail(ErrorCode::ZeroFeed, loc,
                      fmt::format("{} with zero feed rate (no F since G95, or F0)", name()));
    if (ctx.s.spindle_rpm <= 0.0)
      return ctx.fail(
          ErrorCode::ZeroFeed, loc,
          fmt::format("{} with zero spindle speed in feed per revolution (G95)", name()));
    if (ctx.s.spindle_dir == 0)
      return ctx.fail(ErrorCode::ZeroFeed, loc,
                      fmt::format("{} in feed per revolution (G95) with the spindle stopped: the "
                                  "move would never end (M3/M4 first)",
                                  name()));
    return true;
  }
  if (ctx.s.inverse_time) {
    if (!ctx.w.has('F'))
      return ctx.fail(ErrorCode::InverseTimeFeedMissing, loc,
                      fmt::format("{} in inverse time mode (G93) without F on the block", name()));
    if (ctx.inverse_f <= 0.0)
      return ctx.fail(ErrorCode::ZeroFeed, ctx.w['F']->loc,
                      fmt::format("{} with F0 in inverse time mode", name()));
  } else if (ctx.s.feed_mm_min <= 0.0) {
    return ctx.fail(ErrorCode::ZeroFeed, loc,
                    fmt::format("{} with zero feed rate (no F yet, or F0)", name()));
  }
  return true;
}

namespace {

// Wrapped rotary axes given in absolute words (G90, G53): the word names an angle modulo 360,
// turned to in the direction of its sign from where the axis is (in the program's coordinates,
// as LinuxCNC's unwrap_rotary). `target_mm` holds the plain targets; wrapped ones are replaced.
bool unwrap_targets(BlockCtx& ctx, const Pos9& from_mm, unsigned given, Pos9& target_mm) {
  constexpr unsigned kRotary = 0x38u;  // A, B, C
  if ((given & kRotary) == 0) return true;
  for (int i = 3; i <= 5; ++i) {
    if (!(given & (1u << i)) || !axis_wraps(ctx.machine, i)) continue;
    const grammar::Word* aw = ctx.w[kProgramAxisLetters[static_cast<std::size_t>(i)]];
    if (!wrapped_word_ok(aw->value))
      return ctx.fail(
          ErrorCode::ValueOutOfRange, aw->loc,
          fmt::format("{}{:g}: a wrapped rotary axis takes an absolute angle within one "
                      "turn (-360 < {} < 360)",
                      kProgramAxisLetters[static_cast<std::size_t>(i)], aw->value,
                      kProgramAxisLetters[static_cast<std::size_t>(i)]));
    const double offset = target_mm[i] - aw->value;  // program -> machine on this axis
    const double from_program = from_mm[i] - offset;
    target_mm[i] = unwrap_rotary_deg(aw->value, aw->value, from_program) + offset;
  }
  return true;
}

}  // namespace

namespace {

// Every axis of `p` within the position range (false for NaN), in one test of the nine.
bool all_within(const Pos9& p) {
  return (p.array().abs() <= kMaxPositionMm).all();
}

// The end of axis_target: every axis of the target within the position range.
bool target_in_range(BlockCtx& ctx, const Pos9& target_mm) {
  if (all_within(target_mm)) return true;
  for (int i = 0; i < kProgramAxes; ++i) {
    const char letter = kProgramAxisLetters[static_cast<std::size_t>(i)];
    if (within(target_mm[i], kMaxPositionMm)) continue;
    const grammar::Word* aw = ctx.w[letter] ? ctx.w[letter] : ctx.w.polar.first();
    if (aw == nullptr) aw = ctx.w.first_axis;
    return ctx.fail(
        ErrorCode::ValueOutOfRange, aw ? aw->loc : SourceLoc{ctx.block.line, 1},
        fmt::format("{} would move to {:g} mm (offsets included), outside -{:g}..{:g} mm", letter,
                    target_mm[i], kMaxPositionMm, kMaxPositionMm));
  }
  return true;
}

}  // namespace

bool axis_target(BlockCtx& ctx, const Pos9& from_mm, Pos9& target_mm) {
  const double scale = ctx.scale();
  const Frame frame = ctx.frame();
  target_mm = from_mm;
  if (!ctx.w.polar.any() && !frame.rotated()) {
    // The usual block: each axis word on its own axis, by the general path's operations (a word
    // in mm, plus the offsets' sum in G90, plus where the axis is in G91).
    const unsigned given = ctx.w.axes;
    if (given == 0) return target_in_range(ctx, target_mm);
    const bool incremental = ctx.s.incremental;
    for (unsigned m = given; m != 0; m &= m - 1) {
      const int i = std::countr_zero(m);
      const auto* aw = ctx.w[kProgramAxisLetters[static_cast<std::size_t>(i)]];
      const double word = aw->value * (axis_is_rotary(i) ? 1.0 : scale);
      target_mm[i] = incremental ? from_mm[i] + word : word + frame.offset(i);
    }
    if (!incremental && !unwrap_targets(ctx, from_mm, given, target_mm)) return false;
    return target_in_range(ctx, target_mm);
  }
  Pos9 words = Pos9::Zero();  // the axis words in mm (absolute: program coordinates)
  unsigned given = ctx.w.axes;
  for (unsigned m = given; m != 0; m &= m - 1) {
    const int i = std::countr_zero(m);
    const auto* aw = ctx.w[kProgramAxisLetters[static_cast<std::size_t>(i)]];
    const double unit = axis_is_rotary(i) ? 1.0 : scale;  // A, B, C: degrees in G20 and G21
    words[i] = aw->value * unit;
  }
  if (ctx.w.polar.any()) {  // @ radius, ^ angle in place of X, Y (interp/polar.cpp)
    const grammar::Word* pw = ctx.w.polar.first();
    if (ctx.w.has('X') || ctx.w.has('Y'))
      return ctx.fail(ErrorCode::PolarMisused, pw->loc,
                      "polar coordinates (@, ^) cannot be given with X or Y words");
    const Pos9 from_program = frame.to_program(from_mm);
    double x = from_program[0] / scale, y = from_program[1] / scale;
    std::string why;
    if (!polar_end(ctx.w.polar, ctx.s.incremental, x, y, why))
      return ctx.fail(ErrorCode::PolarMisused, pw->loc, why);
    words[0] = x * scale;  // absolute, whatever G90/G91
    words[1] = y * scale;
    target_mm = frame.to_machine(from_mm, words, 3u);
    given &= ~3u;
  }
  if (ctx.s.incremental) {
    double dx = words[0], dy = words[1];
    frame.turn(dx, dy);  // G91 steps are along the program's axes
    words[0] = dx;
    words[1] = dy;
    for (int i = 0; i < kProgramAxes; ++i)
      if (given & (1u << i)) target_mm[i] = from_mm[i] + words[i];
    if (frame.rotated() && (given & 3u)) {  // a step in X alone moves machine X and Y
      target_mm[0] = from_mm[0] + words[0];
      target_mm[1] = from_mm[1] + words[1];
    }
  } else if (given != 0) {
    target_mm = frame.to_machine(target_mm, words, given);
    if (!unwrap_targets(ctx, from_mm, given, target_mm)) return false;
  }
  return target_in_range(ctx, target_mm);
}

bool machine_target(BlockCtx& ctx, Pos9& target_mm) {
  if (ctx.w.polar.any())
    return ctx.fail(ErrorCode::PolarMisused, ctx.w.polar.first()->loc,
                    "polar coordinates (@, ^) cannot be used with G53");
  if (ctx.s.incremental)
    return ctx.fail(ErrorCode::G53Misused, ctx.loc_of(Group::NonModal),
                    "G53 in incremental distance mode (G91): machine coordinates are absolute");
  target_mm = ctx.s.position_mm;
  for (int i = 0; i < kProgramAxes; ++i) {
    const char letter = kProgramAxisLetters[static_cast<std::size_t>(i)];
    const auto* aw = ctx.w[letter];
    if (!aw) continue;
    target_mm[i] = aw->value * (axis_is_rotary(i) ? 1.0 : ctx.scale());
    if (axis_wraps(ctx.machine, i)) {  // the word less the offsets, unwrapped from here
      if (!wrapped_word_ok(aw->value))
        return ctx.fail(ErrorCode::ValueOutOfRange, aw->loc,
                        fmt::format("{}{:g}: a wrapped rotary axis takes an absolute angle within "
                                    "one turn (-360 < {} < 360)",
                                    letter, aw->value, letter));
      const double offset = ctx.offset()[i];
      target_mm[i] =
          unwrap_rotary_deg(aw->value, aw->value - offset, ctx.s.position_mm[i] - offset) + offset;
    }
    if (!within(target_mm[i], kMaxPositionMm))
      return ctx.fail(ErrorCode::ValueOutOfRange, aw->loc,
                      fmt::format("{} would move to {:g} mm, outside -{:g}..{:g} mm", letter,
                                  target_mm[i], kMaxPositionMm, kMaxPositionMm));
  }
  return true;
}

namespace {

// motion_template's fields, set on `mo`.
void set_template(const BlockCtx& ctx, MotionKind kind, Motion& mo) {
  mo.line = ctx.block.line;
  mo.kind = kind;
  mo.plane = ctx.s.plane;
  set_path_mode(ctx, mo);
  if (ctx.s.css) {  // G96 on every move: a spindle with a ramp follows the radius all the time
    mo.spindle_rpm = ctx.s.spindle_rpm;
    mo.css_surface_mm_min = ctx.s.css_surface_mm_min;
    mo.css_max_rpm = ctx.s.css_max_rpm;
    mo.css_axis_x_mm = ctx.offset()[0];
  }
}

// The block's next move, made in place at the end of ctx.out as motion_template makes it (no
// copy of the move).
Motion& new_motion(BlockCtx& ctx, MotionKind kind) {
  Motion& mo = std::get<Motion>(ctx.out.emplace_back(std::in_place_type<Motion>));
  set_template(ctx, kind, mo);
  return mo;
}

// A new move's position `v` (zero, as made) set to to_machine(p, l): the machine's axes alone.
[[gnu::always_inline]] inline void set_machine_axes(AxisVec& v, const Pos9& p,
                                                    const AxisLayout& l) {
  if (!l.is_xyz()) {
    v = to_machine(p, l);
    return;
  }
  v[0] = p[0];
  v[1] = p[1];
  v[2] = p[2];
}

// to_machine(a, l) != to_machine(b, l).
bool differ_on_machine(const Pos9& a, const Pos9& b, const AxisLayout& l) {
  if (l.is_xyz()) return a[0] != b[0] || a[1] != b[1] || a[2] != b[2];
  return to_machine(a, l) != to_machine(b, l);
}

}  // namespace

Motion motion_template(const BlockCtx& ctx, MotionKind kind) {
  Motion mo;
  set_template(ctx, kind, mo);
  return mo;
}

// What every emitted move must meet, whichever step computed it: a target within the position
// range, and room in the block for one more move.
static bool can_emit(BlockCtx& ctx, const Pos9& target_mm, SourceLoc loc) {
  if (all_within(target_mm) && ctx.out.size() < kMaxMovesPerBlock) return true;
  for (int i = 0; i < kProgramAxes; ++i)
    if (!within(target_mm[i], kMaxPositionMm))
      return ctx.fail(ErrorCode::ValueOutOfRange, loc,
                      fmt::format("{} would move to {:g} mm, outside -{:g}..{:g} mm",
                                  kProgramAxisLetters[static_cast<std::size_t>(i)], target_mm[i],
                                  kMaxPositionMm, kMaxPositionMm));
  if (ctx.out.size() >= kMaxMovesPerBlock)
    return ctx.fail(
        ErrorCode::ValueOutOfRange, loc,
        fmt::format("the block expands to more than {} moves (repeats, pecks)", kMaxMovesPerBlock));
  return true;
}

bool emit_straight(BlockCtx& ctx, MotionKind kind, const Pos9& target_mm, SourceLoc loc) {
  if (!can_emit(ctx, target_mm, loc)) return false;
  const Pos9& from = motion_start(ctx);
  if (differ_on_machine(from, target_mm, ctx.machine.layout)) {
    Motion& mo = new_motion(ctx, kind);
    set_machine_axes(mo.start_mm, from, ctx.machine.layout);
    set_machine_axes(mo.end_mm, target_mm, ctx.machine.layout);
    if (kind != MotionKind::Rapid && !set_feed(ctx, mo)) {
      ctx.out.pop_back();
      return false;
    }
  }
  ctx.s.position_mm = target_mm;
  ctx.s.comp.detached = false;
  return true;
}

bool emit_arc(BlockCtx& ctx, const Pos9& target_mm, const Pos9& centre_mm, bool ccw) {
  if (!can_emit(ctx, target_mm, motion_loc(ctx))) return false;
  Motion& mo = new_motion(ctx, MotionKind::Arc);
  set_machine_axes(mo.start_mm, ctx.s.position_mm, ctx.machine.layout);
  set_machine_axes(mo.end_mm, target_mm, ctx.machine.layout);
  set_machine_axes(mo.center_mm, centre_mm, ctx.machine.layout);
  mo.ccw = ccw;
  mo.turns = 1;
  if (!set_feed(ctx, mo)) {
    ctx.out.pop_back();
    return false;
  }
  ctx.s.position_mm = target_mm;
  return true;
}

bool run_straight(BlockCtx& ctx, const Code& c) {
  const SourceLoc loc = motion_loc(ctx);
  if (c.number10 != 0 && !check_feed(ctx, c.number10, loc)) return false;
  ctx.s.comp.arc_not_allowed = false;
  const MotionKind kind = c.number10 == 0 ? MotionKind::Rapid : MotionKind::Line;
  Pos9 target;
  if (ctx.w.has_code('G', 530)) {
    if (ctx.s.comp.active())
      return ctx.fail(ErrorCode::G53Misused, ctx.loc_of(Group::NonModal),
                      "G53 with cutter radius compensation on");
    if (!machine_target(ctx, target)) return false;
  } else if (!axis_target(ctx, comp_program_point(ctx), target)) {
    return false;
  }
  if (ctx.s.comp.active()) return comp_straight(ctx, kind, target);
  return emit_straight(ctx, kind, target, loc);
}

// G33: a straight move synchronised with the spindle, K program units per revolution (LinuxCNC's
// convert_straight for G_33: K required, the spindle turning). gmotion's spindle runs at its
// programmed S from M3/M4 on (no spin-up), so the move is fed at K x S and ignores the feed
// override, as LinuxCNC's synchronised moves do.
bool run_spindle_sync(BlockCtx& ctx, const Code& c) {
  const SourceLoc loc = motion_loc(ctx);
  if (!ctx.w.has('K'))
    return ctx.fail(ErrorCode::MissingWord, loc,
                    "G33 without K (the distance per spindle revolution)");
  if (ctx.s.spindle_dir == 0)
    return ctx.fail(ErrorCode::CycleMisused, loc, "G33 with the spindle not turning (M3/M4 first)");
  const double k_mm = std::fabs(ctx.w.get('K') * ctx.scale());
  if (!(k_mm > 0.0 && ctx.s.spindle_rpm > 0.0))
    return ctx.fail(ErrorCode::ZeroFeed, ctx.w['K']->loc,
                    fmt::format("G33 at K{:g} and S{:g} would never end (zero feed)",
                                ctx.w.get('K'), ctx.s.spindle_rpm));
  if (ctx.s.comp.active())
    return ctx.fail(ErrorCode::CutterCompMisused, loc,
                    fmt::format("{} with cutter radius compensation on", code_name(c)));
  ctx.s.comp.arc_not_allowed = false;
  Pos9 target;
  if (!axis_target(ctx, motion_start(ctx), target)) return false;
  Motion mo = motion_template(ctx, MotionKind::Line);
  mo.start_mm = to_machine(motion_start(ctx), ctx.machine.layout);
  mo.end_mm = to_machine(target, ctx.machine.layout);
  set_spindle_feed(ctx, mo, k_mm);
  mo.spindle_synced = true;
  if (!within(mo.feed_mm_min, kMaxFeedMmMin))
    return ctx.fail(
        ErrorCode::ValueOutOfRange, ctx.w['K']->loc,
        fmt::format("G33 K{:g} at {:g} rpm is {:g} mm/min, beyond {:g} mm/min", ctx.w.get('K'),
                    mo.feed_mm_min / k_mm, mo.feed_mm_min, kMaxFeedMmMin));
  if (mo.end_mm != mo.start_mm) ctx.out.emplace_back(mo);
  ctx.s.position_mm = target;
  ctx.s.comp.detached = false;
  return true;
}

// G33.1: rigid tapping (LinuxCNC's RIGID_TAP): in to the axis words' point synchronised at K per
// revolution, the spindle reverses, and out to where it started at I x that speed (I < 1: 1).
// The tool ends where it began. The spindle's reversal is instant in gmotion's model.
bool run_rigid_tap(BlockCtx& ctx, const Code& c) {
  const SourceLoc loc = motion_loc(ctx);
  if (!ctx.w.has('K'))
    return ctx.fail(ErrorCode::MissingWord, loc,
                    "G33.1 without K (the distance per spindle revolution)");
  if (ctx.s.spindle_dir == 0)
    return ctx.fail(ErrorCode::CycleMisused, loc,
                    "G33.1 with the spindle not turning (M3/M4 first)");
  const double k_mm = std::fabs(ctx.w.get('K') * ctx.scale());
  if (!(k_mm > 0.0 && ctx.s.spindle_rpm > 0.0))
    return ctx.fail(ErrorCode::ZeroFeed, ctx.w['K']->loc,
                    fmt::format("G33.1 at K{:g} and S{:g} would never end (zero feed)",
                                ctx.w.get('K'), ctx.s.spindle_rpm));
  if (!comp_forbids(ctx, loc, code_name(c))) return false;
  const double scale = std::max(1.0, ctx.w.get('I', 1.0));
  Pos9 target;
  if (!axis_target(ctx, ctx.s.position_mm, target)) return false;
  const AxisVec start = to_machine(ctx.s.position_mm, ctx.machine.layout);
  const AxisVec end = to_machine(target, ctx.machine.layout);
  if (end == start) return true;
  Motion in = motion_template(ctx, MotionKind::Line);
  in.start_mm = start;
  in.end_mm = end;
  set_spindle_feed(ctx, in, k_mm);
  in.spindle_synced = true;
  in.canon = LineCanon::RigidTap;
  Motion out = in;
  out.start_mm = end;
  out.end_mm = start;
  out.spindle_rpm *= scale;
  out.css_max_rpm *= scale;
  out.css_surface_mm_min *= scale;
  out.feed_mm_min = k_mm * out.spindle_rpm_at(out.start_mm[0]);
  ctx.out.emplace_back(in);
  ctx.out.emplace_back(out);
  return true;
}

bool arc_centre(BlockCtx& ctx, const Code& c, const Pos9& start, const Pos9& end, Pos9& centre) {
  const BlockWords& w = ctx.w;
  const Frame frame = ctx.frame();
  const double scale = ctx.scale();
  const PlaneAxes ax = plane_axes(ctx.s.plane);
  const char la = "IJK"[ax.a], lb = "IJK"[ax.b];
  if (frame.rotated() && ctx.s.plane != Plane::XY)
    return ctx.fail(
        ErrorCode::UnknownGCode, motion_loc(ctx),
        fmt::format("{} in the {} plane of a rotated coordinate system (G10 L2 R{:g}): "
                    "gmotion's arcs lie in the XY, XZ or YZ plane",
                    code_name(c), ctx.s.plane == Plane::XZ ? "XZ" : "YZ", frame.rotation_deg()));
  ArcInput in;
  if (frame.rotated()) {
    const Pos9 start_p = frame.to_program(start), end_p = frame.to_program(end);
    in.start_a = start_p[ax.a] / scale;
    in.start_b = start_p[ax.b] / scale;
    in.end_a = end_p[ax.a] / scale;
    in.end_b = end_p[ax.b] / scale;
  } else {  // to_program's operations on the plane's two axes only
    const double off_a = frame.offset(ax.a), off_b = frame.offset(ax.b);
    in.start_a = (start[ax.a] - off_a) / scale;
    in.start_b = (start[ax.b] - off_b) / scale;
    in.end_a = (end[ax.a] - off_a) / scale;
    in.end_b = (end[ax.b] - off_b) / scale;
  }
  in.use_r = w.has('R');
  in.r = w.get('R');
  in.off_a = w.get(la);
  in.off_b = w.get(lb);
  in.offsets_absolute = ctx.s.ijk_absolute;
  in.ccw = c.number10 == 30;
  in.mm_per_unit = scale;
  in.rule = ctx.machine.arc_rule;
  ArcResult ar = compute_arc(in);
  const SourceLoc aloc = in.use_r ? w['R']->loc : w.has(la) ? w[la]->loc : w[lb]->loc;
  if (ar.error != ErrorCode::None) return ctx.fail(ar.error, aloc, std::move(ar.message));
  double rel_a = ar.rel_a * scale, rel_b = ar.rel_b * scale;
  frame.turn(rel_a, rel_b);  // rotated: the XY plane, (a, b) = (x, y)
  centre = start;
  centre[ax.a] = start[ax.a] + rel_a;
  centre[ax.b] = start[ax.b] + rel_b;
  for (const int i : {ax.a, ax.b}) {
    if (within(centre[i], kMaxPositionMm)) continue;
    return ctx.fail(ErrorCode::ValueOutOfRange, aloc,
                    fmt::format("arc centre {} = {:g} mm, outside -{:g}..{:g} mm",
                                kProgramAxisLetters[static_cast<std::size_t>(i)], centre[i],
                                kMaxPositionMm, kMaxPositionMm));
  }
  return true;
}

bool run_arc(BlockCtx& ctx, const Code& c) {
  const SourceLoc mloc = motion_loc(ctx);
  if (ctx.s.comp.arc_not_allowed)
    return ctx.fail(ErrorCode::CutterCompMisused, mloc,
                    fmt::format("{} just after G40: the move leaving cutter compensation must be "
                                "straight",
                                code_name(c)));
  if (ctx.w.has_code('G', 530))
    return ctx.fail(ErrorCode::G53Misused, ctx.loc_of(Group::NonModal),
                    fmt::format("G53 with {}: G53 moves need G0 or G1", code_name(c)));
  if (!check_feed(ctx, c.number10, mloc)) return false;
  ModalState& s = ctx.s;
  const BlockWords& w = ctx.w;
  const PlaneAxes ax = plane_axes(s.plane);
  const char la = "IJK"[ax.a], lb = "IJK"[ax.b], ln = "IJK"[ax.n];
  if (w.has(ln))
    return ctx.fail(ErrorCode::ArcOffsetWrongPlane, w[ln]->loc,
                    fmt::format("{} word given for an arc in the {}", ln, plane_text(s.plane)));
  if (w.has('R') && (w.has(la) || w.has(lb)))
    return ctx.fail(ErrorCode::ArcRWithIjk, w['R']->loc, "R given together with I/J/K for an arc");
  if (!w.has('R') && !w.has(la) && !w.has(lb))
    return ctx.fail(ErrorCode::ArcMissingCenter, mloc,
                    fmt::format("arc without R and without {} or {} (centre unknown)", la, lb));
  int turns = 1;
  if (w.has('P')) {
    double p = 0;
    if (!near_integer(w['P']->value, p) || p < 1 || p > 1e6)
      return ctx.fail(
          ErrorCode::BadPWord, w['P']->loc,
          fmt::format("arc P{:g}: P must be an integer of 1 or more (turns)", w['P']->value));
    turns = static_cast<int>(p);
  }
  Pos9 target;
  if (!axis_target(ctx, comp_program_point(ctx), target)) return false;
  if (ctx.s.comp.active()) return comp_arc(ctx, c, target, turns);
  Pos9 center;
  if (!arc_centre(ctx, c, s.position_mm, target, center)) return false;
  Motion& mo = new_motion(ctx, MotionKind::Arc);
  set_machine_axes(mo.start_mm, s.position_mm, ctx.machine.layout);
  set_machine_axes(mo.end_mm, target, ctx.machine.layout);
  set_machine_axes(mo.center_mm, center, ctx.machine.layout);
  mo.ccw = c.number10 == 30;
  mo.turns = turns;
  if (!set_feed(ctx, mo)) {
    ctx.out.pop_back();
    return false;
  }
  s.position_mm = target;
  return true;
}

}  // namespace gm
