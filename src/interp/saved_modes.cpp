// M70 (save the modes), M71 (forget them), M72 (restore them), M73 (save, restore when the
// subroutine returns), as LinuxCNC 2.9 does: one context per subroutine call level.
#include "interp/steps.hpp"

#include <cstdlib>

namespace gm {

namespace {

SavedModes save(const ModalState& s) {
  SavedModes m;
  m.valid = true;
  m.inch = s.inch;
  m.incremental = s.incremental;
  m.ijk_absolute = s.ijk_absolute;
  m.inverse_time = s.inverse_time;
  m.per_rev = s.per_rev;
  m.retract_to_r = s.retract_to_r;
  m.plane = s.plane;
  m.comp_code = s.comp.side > 0 ? 410 : s.comp.side < 0 ? 420 : 400;
  m.tool_length_code = s.tool_length_code;
  m.coord_system = s.coord_system;
  m.path_mode = s.path_mode;
  m.path_tolerance_mm = s.path_tolerance_mm;
  m.naive_cam_tolerance_mm = s.naive_cam_tolerance_mm;
  m.feed_units = s.feed_mm_min / s.mm_per_unit();
  m.speed_rpm = s.spindle_rpm;
  m.spindle_dir = s.spindle_dir;
  m.feed_override = s.feed_override;
  m.mist = s.mist;
  m.flood = s.flood;
  return m;
}

// A value as LinuxCNC's restore writes it into the G-code it executes (F%.1f, S%.0f).
double printed(double v, int decimals) {
  return std::strtod(fmt::format("{:.{}f}", v, decimals).c_str(), nullptr);
}

bool run(BlockCtx& ctx, char letter, int number10) {
  const Code* c = find_code(letter, number10);
  return c == nullptr || c->run(ctx, *c);
}

int plane_code(Plane p) {
  return p == Plane::XY ? 170 : p == Plane::XZ ? 180 : 190;
}
int coord_code(int cs) {
  return cs < 6 ? 540 + 10 * cs : 590 + (cs - 5);
}

}  // namespace

bool restore_modes(BlockCtx& ctx, const SavedModes& m) {
  ModalState& s = ctx.s;
  // G20/G21 first, so that F is read in the saved units.
  if (s.inch != m.inch && !run(ctx, 'G', m.inch ? 200 : 210)) return false;
  // One block "F.. S.. G.." in the order of execution: feed mode, F, S, plane, compensation,
  // tool length, coordinate system, path control, distance, retract mode.
  if ((s.inverse_time != m.inverse_time || s.per_rev != m.per_rev) && !run(ctx, 'G',
                                                                           m.inverse_time ? 930
                                                                           : m.per_rev    ? 950
                                                                                          : 940))
    return false;
  if (!s.inverse_time) s.feed_mm_min = printed(m.feed_units, 1) * s.mm_per_unit();
  // S: rs274 2.9 prints SET_SPINDLE_SPEED only when the speed changes.
  if (const double rpm = printed(m.speed_rpm, 0); rpm != s.spindle_rpm) {
    s.spindle_rpm = rpm;
    emit_io(ctx, EventKind::SpindleSpeed, 0, rpm);
  }
  if (s.plane != m.plane && !run(ctx, 'G', plane_code(m.plane))) return false;
  const int comp_code = s.comp.side > 0 ? 410 : s.comp.side < 0 ? 420 : 400;
  if (comp_code != m.comp_code && !run(ctx, 'G', m.comp_code)) return false;
  if (s.tool_length_code != m.tool_length_code && !run(ctx, 'G', m.tool_length_code)) return false;
  if (s.coord_system != m.coord_system && !run(ctx, 'G', coord_code(m.coord_system))) return false;
  if (m.path_mode == PathMode::Continuous) {  // G64 P Q is always written again
    if (!comp_forbids(ctx, SourceLoc{ctx.block.line, 1}, "change the path control mode"))
      return false;
    s.path_mode = PathMode::Continuous;
    s.path_tolerance_mm = m.path_tolerance_mm;
    s.naive_cam_tolerance_mm = m.naive_cam_tolerance_mm;
  } else if (s.path_mode != m.path_mode &&
             !run(ctx, 'G', m.path_mode == PathMode::ExactPath ? 610 : 611)) {
    return false;
  }
  s.incremental = m.incremental;
  s.ijk_absolute = m.ijk_absolute;
  if (s.retract_to_r != m.retract_to_r && !run(ctx, 'G', m.retract_to_r ? 990 : 980)) return false;
  // The M codes that differ, each on a line of its own: spindle, mist (M7 or M9), flood (M8 or
  // M9), compared with the modes before the restore (an M9 for mist turns flood off too).
  const bool mist_was = s.mist, flood_was = s.flood;
  if (s.spindle_dir != m.spindle_dir && !run(ctx, 'M',
                                             m.spindle_dir > 0   ? 30
                                             : m.spindle_dir < 0 ? 40
                                                                 : 50))
    return false;
  if (mist_was != m.mist && !run(ctx, 'M', m.mist ? 70 : 90)) return false;
  if (flood_was != m.flood && !run(ctx, 'M', m.flood ? 80 : 90)) return false;
  if (s.feed_override != m.feed_override && !run(ctx, 'M', m.feed_override ? 480 : 490))
    return false;
  return true;
}

bool run_modes_save(BlockCtx& ctx, const Code& c) {
  const auto level = static_cast<std::size_t>(std::clamp(ctx.call_level, 0, kCallLevels - 1));
  switch (c.number10) {
    case 700:
    case 730: {
      SavedModes m = save(ctx.s);
      m.restore_on_return = c.number10 == 730 && level > 0;  // M73 at the top: saved only
      ctx.tables_w().saved_modes[level] = m;
      return true;
    }
    case 710:
      ctx.tables_w().saved_modes[level].valid = false;
      return true;
    default: {  // 720
      const SavedModes m = ctx.tables().saved_modes[level];
      if (!m.valid)
        return ctx.fail(ErrorCode::MissingWord, ctx.loc_of(Group::MSpindle),
                        "M72 with no modes saved at this call level (M70 or M73 first)");
      return restore_modes(ctx, m);
    }
  }
}

}  // namespace gm
