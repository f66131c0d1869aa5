// The offset and reference-point steps: G54..G59.3, G10 L2/L20, G92/G92.1/G92.2/G92.3, G52,
// G28/G28.1/G30/G30.1, as LinuxCNC 2.9 runs them. Positions are machine coordinates (mm).
#include "interp/rotary_wrap.hpp"
#include "interp/steps.hpp"

namespace gm {

namespace {

// G92, G52 and G10 L20 name where the current point is: on a wrapped axis, an angle within one
// turn (LinuxCNC refuses the rest likewise).
bool wrapped_words_ok(BlockCtx& ctx, const char* code) {
  for (int i = 3; i <= 5; ++i) {
    const char letter = kProgramAxisLetters[static_cast<std::size_t>(i)];
    const grammar::Word* aw = ctx.w[letter];
    if (aw && axis_wraps(ctx.machine, i) && !wrapped_word_ok(aw->value))
      return ctx.fail(ErrorCode::ValueOutOfRange, aw->loc,
                      fmt::format("{} {}{:g}: a wrapped rotary axis takes an angle within one "
                                  "turn (-360 < {} < 360)",
                                  code, letter, aw->value, letter));
  }
  return true;
}

}  // namespace

bool run_coord_system(BlockCtx& ctx, const Code& c) {
  if (!comp_forbids(ctx, ctx.loc_of(Group::CoordSystem), "change coordinate systems")) return false;
  // G54..G59 = 0..5, G59.1..G59.3 = 6..8.
  const int cs = c.number10 <= 590 ? (c.number10 - 540) / 10 : 5 + (c.number10 - 590);
  // The same system again changes nothing: its offsets stay as they were taken (LinuxCNC:
  // "continuing to use same coordinate system"), whatever its parameters hold now.
  if (cs != ctx.s.coord_system) select_coord_system(ctx.s, ctx.tables(), cs);
  return true;
}

bool run_g10(BlockCtx& ctx, const Code&) {
  const SourceLoc loc = ctx.loc_of(Group::NonModal);
  if (!ctx.w.has('L')) return ctx.fail(ErrorCode::MissingWord, loc, "G10 without L");
  const auto* lw = ctx.w['L'];
  double l = 0;
  if (!near_integer(lw->value, l) || (l != 1 && l != 2 && l != 10 && l != 11 && l != 20))
    return ctx.fail(ErrorCode::BadLWord, lw->loc,
                    fmt::format("G10 L{:g}: L must be 1, 2, 10, 11 or 20", lw->value));
  if (!ctx.w.has('P'))
    return ctx.fail(ErrorCode::MissingWord, loc, fmt::format("G10 L{:g} without P", l));
  if (l == 1 || l == 10 || l == 11) return run_g10_tool(ctx, static_cast<int>(l));

  const auto* pw = ctx.w['P'];
  double p = 0;
  if (!near_integer(pw->value, p) || p < 0 || p > 9)
    return ctx.fail(ErrorCode::BadCoordSystem, pw->loc,
                    fmt::format("G10 L{:g} P{:g}: P must be 0 (current) to 9", l, pw->value));
  if (ctx.w.has('I') || ctx.w.has('J'))
    return ctx.fail(ErrorCode::UnusedWord, ctx.w.has('I') ? ctx.w['I']->loc : ctx.w['J']->loc,
                    fmt::format("G10 L{:g}: I and J words are not allowed", l));
  if (l == 20 && !wrapped_words_ok(ctx, "G10 L20")) return false;
  const auto* rw = ctx.w['R'];
  if (rw && l == 20)
    return ctx.fail(ErrorCode::UnusedWord, rw->loc,
                    "G10 L20 with R: the rotation is set with G10 L2");
  const std::size_t cs =
      p == 0 ? static_cast<std::size_t>(ctx.s.coord_system) : static_cast<std::size_t>(p) - 1;
  if (cs == static_cast<std::size_t>(ctx.s.coord_system) &&
      !comp_forbids(ctx, loc, "change the active coordinate system"))
    return false;
  // L20 needs the current point in system `cs` before anything changes (LinuxCNC's
  // find_current_in_system): in that system's old offsets and rotation.
  ModalState in_cs = ctx.s;
  select_coord_system(in_cs, ctx.tables(), static_cast<int>(cs));
  const Pos9 here = Frame(in_cs).to_program(ctx.s.position_mm);
  const double rotation = rw ? rw->value : ctx.tables().g5x_rotation_deg[cs];
  if (rw && !within(rotation, 1e9))
    return ctx.fail(ErrorCode::ValueOutOfRange, rw->loc, fmt::format("G10 L2 R{:g}", rotation));
  SystemTables& t = ctx.tables_w();
  Pos9& g5x = t.g5x_mm[cs];
  t.g5x_rotation_deg[cs] = rotation;
  for (int i = 0; i < kProgramAxes; ++i) {
    const auto* aw = ctx.w[kProgramAxisLetters[static_cast<std::size_t>(i)]];
    if (!aw) continue;
    const double v =
        aw->value * (axis_is_rotary(i) ? 1.0 : ctx.scale());  // absolute whatever G90/G91
    if (l == 2)
      g5x[i] = v;
    else  // L20: the current point gets coordinate v in that system
      g5x[i] = ctx.s.position_mm[i] - ctx.s.g92_mm[i] - ctx.s.tool_offset_mm[i] - v;
  }
  if (l == 20 && rotation != 0.0 && (ctx.w.has('X') || ctx.w.has('Y'))) {
    // Rotated: the new origin is the old one moved by the turned difference between the
    // current point and the point wanted (both in the rotated system).
    double dx = here[0] - (ctx.w.has('X') ? ctx.w['X']->value * ctx.scale() : here[0]);
    double dy = here[1] - (ctx.w.has('Y') ? ctx.w['Y']->value * ctx.scale() : here[1]);
    rotate_xy(dx, dy, rotation);
    const Pos9& old = ctx.committed.g5x_mm[cs];
    g5x[0] = old[0] + dx;
    g5x[1] = old[1] + dy;
  }
  // The active system takes its new values at once (LinuxCNC: p_int == origin_index).
  if (cs == static_cast<std::size_t>(ctx.s.coord_system))
    select_coord_system(ctx.s, ctx.tables(), ctx.s.coord_system);
  return true;
}

bool run_g92(BlockCtx& ctx, const Code&) {
  if (!comp_forbids(ctx, ctx.loc_of(Group::NonModal), "change axis offsets")) return false;
  if (!wrapped_words_ok(ctx, "G92")) return false;
  if (!ctx.w.first_axis)
    return ctx.fail(ErrorCode::G92WithoutAxes, ctx.loc_of(Group::NonModal),
                    "G92 without axis words");
  // The current point gets the coordinates given: G92 is added before the rotation, so the
  // offset is the current point's in the rotated system (with no G92) minus the value.
  const Pos9 here = ctx.frame().to_program(ctx.s.position_mm) + ctx.s.g92_mm;
  Pos9& g92 = ctx.s.g92_mm;
  ctx.s.g92_applied = true;
  ctx.s.g92_flag = 1.0;
  for (int i = 0; i < kProgramAxes; ++i) {
    const auto* aw = ctx.w[kProgramAxisLetters[static_cast<std::size_t>(i)]];
    if (!aw) continue;
    const double v = aw->value * (axis_is_rotary(i) ? 1.0 : ctx.scale());
    if (ctx.frame().rotated() && i < 2) {
      g92[i] = here[i] - v;
      continue;
    }
    g92[i] = 0.0;
    g92[i] = ctx.s.position_mm[i] - ctx.offset()[i] - v;
  }
  ctx.tables_w().g92_saved_mm = g92;
  return true;
}

bool run_g52(BlockCtx& ctx, const Code&) {
  if (!comp_forbids(ctx, ctx.loc_of(Group::NonModal), "change axis offsets")) return false;
  if (!wrapped_words_ok(ctx, "G52")) return false;
  Pos9& g92 = ctx.s.g92_mm;  // LinuxCNC keeps the G52 local offset in the G92 offsets
  ctx.s.g92_applied = true;
  ctx.s.g92_flag = 1.0;
  for (int i = 0; i < kProgramAxes; ++i)
    if (const auto* aw = ctx.w[kProgramAxisLetters[static_cast<std::size_t>(i)]])
      g92[i] = aw->value * (axis_is_rotary(i) ? 1.0 : ctx.scale());
  ctx.tables_w().g92_saved_mm = g92;
  return true;
}

bool run_g92_x(BlockCtx& ctx, const Code& c) {
  if (!comp_forbids(ctx, ctx.loc_of(Group::NonModal), "change axis offsets")) return false;
  ctx.s.g92_applied = c.number10 == 923;
  ctx.s.g92_flag = ctx.s.g92_applied ? 1.0 : 0.0;
  switch (c.number10) {
    case 921:  // reset, parameters too
      ctx.s.g92_mm.setZero();
      ctx.tables_w().g92_saved_mm.setZero();
      break;
    case 922:  // reset, parameters kept
      ctx.s.g92_mm.setZero();
      break;
    default:  // 923: apply the parameters
      ctx.s.g92_mm = ctx.tables().g92_saved_mm;
      break;
  }
  return true;
}

bool run_home_set(BlockCtx& ctx, const Code& c) {
  Pos9& home = c.number10 == 281 ? ctx.tables_w().g28_mm : ctx.tables_w().g30_mm;
  home = ctx.s.position_mm;
  for (int i = 3; i <= 5; ++i)  // a wrapped axis stores its angle within one turn
    if (axis_wraps(ctx.machine, i)) home[i] = wrap_360(home[i]);
  return true;
}

bool run_home(BlockCtx& ctx, const Code& c) {
  const SourceLoc loc = ctx.loc_of(Group::NonModal);
  Pos9 via;  // the intermediate point (the axis words, G90/G91 and offsets as for G0)
  if (!axis_target(ctx, ctx.s.position_mm, via)) return false;
  if (!comp_forbids(ctx, loc, fmt::format("use {}", code_name(c)))) return false;
  if (!emit_straight(ctx, MotionKind::Rapid, via, loc)) return false;
  const Pos9& home = c.number10 == 280 ? ctx.tables().g28_mm : ctx.tables().g30_mm;
  Pos9 target = ctx.s.position_mm;
  const bool all = ctx.w.first_axis == nullptr;
  unsigned mask = 0;
  for (int i = 0; i < kProgramAxes; ++i)
    if (all || ctx.w.has(kProgramAxisLetters[static_cast<std::size_t>(i)])) {
      target[i] = home[i];
      mask |= 1u << i;
    }
  // The words name program axes (LinuxCNC's find_relative of the stored point): in a turned
  // system, homing Y alone moves along program Y, which mixes machine X and Y.
  if (const Frame f = ctx.frame(); f.rotated() && (mask & 3u))
    target = f.to_machine(ctx.s.position_mm, f.to_program(home), mask);
  return emit_straight(ctx, MotionKind::Rapid, target, loc);
}

}  // namespace gm
