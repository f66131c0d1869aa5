// G76, the lathe threading cycle: passes of spindle-synchronised cuts at degressing depths, with
// a compound angle, entry/exit tapers and spring passes, expanded into moves as LinuxCNC 2.9
// does (its documented G76 and the rs274 output it is checked against, tests/diff/machine).
#include "interp/cutter_comp.hpp"
#include "interp/steps.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace gm {

namespace {

constexpr int kMaxPasses = 10000;

// The cycle's geometry in program millimetres: X is the radius axis, Z the thread's axis.
struct Thread {
  double drive_x = 0.0;      ///< the drive line: where the tool is when G76 starts
  double start_z = 0.0;      ///< the thread starts here ...
  double end_z = 0.0;        ///< ... and ends here (Z word), shifted by the compound angle
  double side = -1.0;        ///< -1 external thread (I < 0: cut towards the axis), +1 boring
  double first_depth = 0.0;  ///< |I|: from the drive line to the thread's crest
  double step = 0.0;         ///< |J|: the first cut's depth
  double height = 0.0;       ///< |K|: the thread's full depth
  double pitch = 0.0;        ///< P: mm per revolution along Z
  double tan_angle = 0.0;    ///< tan of the compound angle Q (sign by direction)
  double degression = 1.0;   ///< R: cut depth grows as pass^(1/R)
  double taper = 0.0;        ///< E: the taper's length along Z (signed by direction)
  double taper_pitch = 0.0;  ///< mm per revolution along the tapered path
  bool entry_taper = false, exit_taper = false;  ///< L bits 1 and 2
  int spring_passes = 0;                         ///< H
};

struct ThreadRun {
  BlockCtx& ctx;
  const Thread& t;
  Pos9 base;  ///< the machine position with X and Z replaced per move

  Pos9 at(double x, double z) const {
    Pos9 p = Pos9::Zero();
    p[0] = x;
    p[2] = z;
    return ctx.frame().to_machine(base, p, 0b101u);
  }
  bool rapid(double x, double z) {
    return emit_straight(ctx, MotionKind::Rapid, at(x, z), SourceLoc{ctx.block.line, 1});
  }
  // A cut synchronised with the spindle, `mm_per_rev` along the path per revolution.
  void cut(double x, double z, double mm_per_rev) {
    Motion mo = motion_template(ctx, MotionKind::Line);
    mo.start_mm = to_machine(ctx.s.position_mm, ctx.machine.layout);
    const Pos9 end = at(x, z);
    mo.end_mm = to_machine(end, ctx.machine.layout);
    set_spindle_feed(ctx, mo, mm_per_rev);
    mo.spindle_synced = true;
    if (mo.end_mm != mo.start_mm) ctx.out.emplace_back(mo);
    ctx.s.position_mm = end;
  }
  // One pass at `depth` below the drive line, the start shifted `zoff` by the compound angle:
  // back off, in (tapered or not), along the thread, out (tapered or not), back off.
  bool pass(double depth, double zoff) {
    const double x_back = t.drive_x + t.side * (depth - t.first_depth - t.height);
    const double x_cut = t.drive_x + t.side * depth;
    const double x_crest = t.drive_x + t.side * (depth - t.height);
    const double z0 = t.start_z - zoff, z1 = t.end_z - zoff;
    if (!rapid(x_back, z0)) return false;
    if (t.taper != 0.0 && t.entry_taper) {
      cut(x_crest, z0, t.taper_pitch);
      cut(x_cut, z0 - t.taper, t.taper_pitch);
    } else if (!rapid(x_cut, z0)) {
      return false;
    }
    if (t.taper != 0.0 && t.exit_taper) {
      cut(x_cut, z1 + t.taper, t.pitch);
      cut(x_crest, z1, t.taper_pitch);
    } else {
      cut(x_cut, z1, t.pitch);
    }
    return rapid(x_back, z1);
  }
};

}  // namespace

bool run_threading(BlockCtx& ctx, const Code& c) {
  const BlockWords& w = ctx.w;
  const SourceLoc loc = w.word_of(Group::Motion) ? w.word_of(Group::Motion)->loc
                        : w.first_axis           ? w.first_axis->loc
                                                 : SourceLoc{ctx.block.line, 1};
  // rs274's checks, in its order.
  if (!w.has('P')) return ctx.fail(ErrorCode::MissingWord, loc, "G76 without P (the pitch)");
  if (!w.has('I') || !w.has('J') || !w.has('K'))
    return ctx.fail(ErrorCode::MissingWord, loc,
                    "G76 needs I (drive line to crest), J (first cut) and K (thread depth)");
  if (w.first_axis == nullptr)
    return ctx.fail(ErrorCode::MissingWord, loc, "G76 without an axis word (the thread's end Z)");
  if (ctx.s.spindle_dir == 0)
    return ctx.fail(ErrorCode::CycleMisused, loc, "G76 with the spindle not turning (M3/M4 first)");
  if (!comp_forbids(ctx, loc, "use the G76 threading cycle")) return false;
  if (ctx.s.spindle_rpm <= 0.0)
    return ctx.fail(ErrorCode::ZeroFeed, loc, "G76 with spindle speed 0: it would never end");
  // Under G7, I J K are diameters; LinuxCNC halves them again when G7 is switched on in this
  // very block (and doubles them when G8 is): lathe_ijk_switch.
  const double u = ctx.scale() * ctx.lathe_ijk_switch * (ctx.s.lathe_diameter ? 0.5 : 1.0);
  const double i = w.get('I') * u, j = w.get('J') * u, k = w.get('K') * u;
  if (i == 0.0) return ctx.fail(ErrorCode::CycleMisused, w['I']->loc, "G76 with I0");
  if (j <= 0.0) return ctx.fail(ErrorCode::CycleMisused, w['J']->loc, "G76 needs J > 0");
  if (k <= j) return ctx.fail(ErrorCode::CycleMisused, w['K']->loc, "G76 needs K > J");

  Pos9 end;
  if (!axis_target(ctx, ctx.s.position_mm, end)) return false;
  const Frame frame = ctx.frame();
  const Pos9 here = frame.to_program(ctx.s.position_mm);
  Thread t;
  t.drive_x = here[0];
  t.start_z = here[2];
  const double end_z = frame.to_program(end)[2];
  const double toward = end_z > t.start_z ? -1.0 : 1.0;  // a thread cut towards +Z mirrors
  t.side = i > 0.0 ? 1.0 : -1.0;
  t.first_depth = std::fabs(i);
  t.step = std::fabs(j);
  t.height = std::fabs(k);
  t.pitch = w.get('P') * ctx.scale();
  double q = w.get('Q');
  if (q == -1.0) q = 0.0;
  t.tan_angle =
      std::tan(toward * static_cast<double>(q * 3.14159265358979323846264338327950288L / 180.0L));
  t.degression = w.has('R') && w.get('R') >= 1.0 ? w.get('R') : 1.0;
  const double e = w.has('E') ? std::max(0.0, w.get('E') * ctx.scale()) : 0.0;
  t.taper_pitch = e > 0.0 ? t.pitch * std::hypot(e, t.height) / e : t.pitch;
  t.taper = toward * e;
  const int flags = std::max(0, static_cast<int>(w.get('L')));
  t.entry_taper = (flags & 1) != 0;
  t.exit_taper = (flags & 2) != 0;
  if (w.has('H')) {  // spring passes: a whole number (rs274: "Non integer value for integer")
    double h = 0;
    if (!near_integer(w.get('H'), h) || h > kMaxPasses)
      return ctx.fail(ErrorCode::CycleMisused, w['H']->loc,
                      fmt::format("G76 H{:g}: the spring passes must be a whole number up to {}",
                                  w.get('H'), kMaxPasses));
    t.spring_passes = static_cast<int>(h);
  }
  t.end_z = end_z + t.height * t.tan_angle;

  ThreadRun run{ctx, t, ctx.s.position_mm};
  const double last = t.height + t.first_depth;
  const auto zoff = [&](double depth) { return (depth - t.first_depth) * t.tan_angle; };
  int n = 1;
  for (double depth = t.first_depth + t.step; depth < last;
       depth = t.first_depth + t.step * std::pow(++n, 1.0 / t.degression)) {
    if (n > kMaxPasses)  // a block's moves are held until it ends: keep them bounded
      return ctx.fail(ErrorCode::CycleMisused, loc,
                      fmt::format("G76 would cut more than {} passes (K/J = {:g}, R {:g})",
                                  kMaxPasses, t.height / t.step, t.degression));
    if (!run.pass(depth, zoff(depth))) return false;
  }
  for (int p = 0; p <= t.spring_passes; ++p)
    if (!run.pass(last, zoff(last))) return false;
  static_cast<void>(c);
  return emit_straight(ctx, MotionKind::Rapid, end, loc);
}

}  // namespace gm
