// Canned cycles G73, G74, G81..G89 with G98/G99, R, L, P, Q, incremental mode and every plane,
// expanded into moves as LinuxCNC 2.9 expands them (interp_cycles.cc semantics). A cycle is one
// row of kCycles (the words it needs, its spindle rule) and one body that drills one hole.
#include "interp/steps.hpp"

#include "common/units.hpp"

#include <cmath>
#include <cstdint>

namespace gm {

namespace {

// G73/G83 back-off after each peck: 0.010 inch (0.254 mm in G21), as LinuxCNC.
constexpr double kPeckRapidDeltaInch = 0.010;

// The plane's axes (a, b) and the cycle axis c, as program-axis indices (LinuxCNC: XY -> Z,
// XZ -> Y with a = Z and b = X, YZ -> X with a = Y and b = Z).
struct CycleAxes {
  int a, b, c;
};
CycleAxes cycle_axes(Plane p) {
  switch (p) {
    case Plane::XZ:
      return {2, 0, 1};
    case Plane::YZ:
      return {1, 2, 0};
    case Plane::XY:
      break;
  }
  return {0, 1, 2};
}

// One cycle being expanded: positions in program units along (a, b, c); emits machine moves.
struct CycleRun {
  BlockCtx& ctx;
  CycleAxes ax;
  SourceLoc loc;

  Pos9 machine(double a, double b, double c) const {
    const double u = ctx.scale();
    Pos9 p = Pos9::Zero();
    p[ax.a] = a * u;
    p[ax.b] = b * u;
    p[ax.c] = c * u;
    return ctx.frame().to_machine(ctx.s.position_mm, p, (1u << ax.a) | (1u << ax.b) | (1u << ax.c));
  }
  bool traverse(double a, double b, double c) {
    return emit_straight(ctx, MotionKind::Rapid, machine(a, b, c), loc);
  }
  bool feed(double a, double b, double c) {
    return emit_straight(ctx, MotionKind::Line, machine(a, b, c), loc);
  }
  void dwell(double s) { emit_in_order(ctx, Dwell{ctx.block.line, s}); }
  /// G88's retract by hand during its program stop: a rapid marked as the operator's.
  bool operator_retract(double a, double b, double c) {
    const std::size_t n = ctx.out.size();
    if (!traverse(a, b, c)) return false;
    if (ctx.out.size() > n)
      if (auto* m = std::get_if<Motion>(&ctx.out.back())) m->by_operator = true;
    return true;
  }
  /// G88's program stop (M0): the operator retracts by hand, the run holds for the pause time.
  void program_stop() {
    Event e;
    e.line = ctx.block.line;
    e.kind = EventKind::Pause;
    e.index = 0;
    emit_in_order(ctx, Canon(std::in_place_type<Event>, std::move(e)));
    if (ctx.machine.pause_s > 0.0)
      emit_in_order(ctx, Dwell{ctx.block.line, ctx.machine.pause_s, true});
  }
  /// The spindle's canon within a cycle: stop, then turn `dir` (+1 cw, -1 ccw; 0 stays stopped).
  void spindle(int dir) {
    emit_io(ctx, EventKind::SpindleStop, 0, 0.0);
    if (dir != 0) emit_io(ctx, EventKind::SpindleStart, dir, ctx.s.spindle_rpm);
  }
};

const char* plane_letters(Plane p) {
  return p == Plane::XY ? "XY" : p == Plane::XZ ? "XZ" : "YZ";
}

// One hole of a cycle, in program units: its place (a, b) in the plane and the levels along the
// cycle axis, with the words the cycle bodies use.
struct Hole {
  double a = 0, b = 0;
  double r = 0;              ///< the R plane
  double bottom = 0;         ///< the hole bottom
  double clear = 0;          ///< where the tool leaves the hole: R (G99) or the initial level (G98)
  double p = 0;              ///< dwell, s
  double q = 0;              ///< peck depth
  double peck_back_off = 0;  ///< G73/G83: above the last depth after each peck
  double bore_da = 0, bore_db = 0;  ///< G87: the offset that clears the bore
  double bore_top = 0;              ///< G87: the back bore's top
};

// G81: feed in, rapid out.
bool cycle_g81(CycleRun& run, const Hole& h) {
  return run.feed(h.a, h.b, h.bottom) && run.traverse(h.a, h.b, h.clear);
}

// G73 (chip break: feed a peck, back off a little) and G83 (peck: feed a peck, out to R, back
// down to just above the last depth).
bool peck_drill(CycleRun& run, const Hole& h, bool chip_break) {
  bool ok = true;
  for (double depth = h.r - h.q; ok && depth > h.bottom; depth -= h.q) {
    ok = run.feed(h.a, h.b, depth) && (chip_break || run.traverse(h.a, h.b, h.r)) &&
         run.traverse(h.a, h.b, depth + h.peck_back_off);
  }
  return ok && run.feed(h.a, h.b, h.bottom) && run.traverse(h.a, h.b, h.clear);
}
bool cycle_g73(CycleRun& run, const Hole& h) {
  return peck_drill(run, h, true);
}
bool cycle_g83(CycleRun& run, const Hole& h) {
  return peck_drill(run, h, false);
}

// G74 and G84 (tapping): feed in, spindle reverses, dwell, feed out, spindle as it was.
bool cycle_tap(CycleRun& run, const Hole& h) {
  const ModalState& s = run.ctx.s;
  bool ok = run.feed(h.a, h.b, h.bottom);
  if (ok) {
    run.spindle(-s.spindle_dir);
    run.dwell(h.p);
  }
  ok = ok && run.feed(h.a, h.b, h.clear);
  if (ok) run.spindle(s.spindle_dir);
  return ok;
}

// G82: feed in, dwell, rapid out.
bool cycle_g82(CycleRun& run, const Hole& h) {
  bool ok = run.feed(h.a, h.b, h.bottom);
  if (ok) run.dwell(h.p);
  return ok && run.traverse(h.a, h.b, h.clear);
}

// G85: feed in, feed out to R, rapid to clear.
bool cycle_g85(CycleRun& run, const Hole& h) {
  return run.feed(h.a, h.b, h.bottom) && run.feed(h.a, h.b, h.r) && run.traverse(h.a, h.b, h.clear);
}

// G86: as G82 with the spindle stopped on the way out.
bool cycle_g86(CycleRun& run, const Hole& h) {
  const ModalState& s = run.ctx.s;
  bool ok = run.feed(h.a, h.b, h.bottom);
  if (ok) run.dwell(h.p);
  if (ok) run.spindle(0);
  ok = ok && run.traverse(h.a, h.b, h.clear);
  if (ok) emit_io(run.ctx, EventKind::SpindleStart, s.spindle_dir, s.spindle_rpm);
  return ok;
}

// G87 (back boring): down beside the bore with the spindle oriented, centre, cut up to the top
// and back, orient again, out beside the bore, centre at clear.
bool cycle_g87(CycleRun& run, const Hole& h) {
  const ModalState& s = run.ctx.s;
  const double a = h.a, b = h.b, oa = h.a + h.bore_da, ob = h.b + h.bore_db;
  const auto orient = [&] {
    run.spindle(0);
    emit_io(run.ctx, EventKind::SpindleOrient, s.spindle_dir > 0 ? 2 : 3, 0.0);
  };
  bool ok = run.traverse(oa, ob, h.r);
  if (ok) orient();
  ok = ok && run.traverse(oa, ob, h.bottom) && run.traverse(a, b, h.bottom);
  if (ok) emit_io(run.ctx, EventKind::SpindleStart, s.spindle_dir, s.spindle_rpm);
  ok = ok && run.feed(a, b, h.bore_top) && run.feed(a, b, h.bottom);
  if (ok) orient();
  ok = ok && run.traverse(oa, ob, h.bottom) && run.traverse(oa, ob, h.clear) &&
       run.traverse(a, b, h.clear);
  if (ok) emit_io(run.ctx, EventKind::SpindleStart, s.spindle_dir, s.spindle_rpm);
  return ok;
}

// G88: feed in, dwell, spindle off, program stop: the operator retracts by hand to the
// clearance height (where LinuxCNC's interpreter then takes the tool to be), spindle on again.
bool cycle_g88(CycleRun& run, const Hole& h) {
  const ModalState& s = run.ctx.s;
  bool ok = run.feed(h.a, h.b, h.bottom);
  if (ok) {
    run.dwell(h.p);
    run.spindle(0);
    run.program_stop();
  }
  ok = ok && run.operator_retract(h.a, h.b, h.clear);
  if (ok) emit_io(run.ctx, EventKind::SpindleStart, s.spindle_dir, s.spindle_rpm);
  return ok;
}

// G89: feed in, dwell, feed out to clear.
bool cycle_g89(CycleRun& run, const Hole& h) {
  bool ok = run.feed(h.a, h.b, h.bottom);
  if (ok) run.dwell(h.p);
  return ok && run.feed(h.a, h.b, h.clear);
}

// What a cycle asks of the spindle before it starts.
enum class SpindleRule : std::uint8_t {
  Any,
  Turning,           ///< M3 or M4
  Clockwise,         ///< M3 (G84)
  Counterclockwise,  ///< M4 (G74)
};

// One canned cycle: its code, the words it needs on entering (P dwell, Q peck, G87's I J K),
// its spindle rule and its body (one hole, from above the R plane back to the clearance height).
struct CycleRow {
  int number10;
  bool needs_p, needs_q, needs_ijk;
  SpindleRule spindle;
  bool (*body)(CycleRun&, const Hole&);
};

using SR = SpindleRule;
constexpr CycleRow kCycles[] = {
    // clang-format off
    // G  P      Q      IJK    spindle               body
    {810, false, false, false, SR::Any,              cycle_g81},
    {730, false, true,  false, SR::Any,              cycle_g73},
    {740, false, false, false, SR::Counterclockwise, cycle_tap},
    {820, true,  false, false, SR::Any,              cycle_g82},
    {830, false, true,  false, SR::Any,              cycle_g83},
    {840, false, false, false, SR::Clockwise,        cycle_tap},
    {850, false, false, false, SR::Any,              cycle_g85},
    {860, true,  false, false, SR::Turning,          cycle_g86},
    {870, false, false, true,  SR::Turning,          cycle_g87},
    {880, true,  false, false, SR::Turning,          cycle_g88},
    {890, true,  false, false, SR::Any,              cycle_g89},
    // clang-format on
};

// The row of cycle `g` (G81's for a code without one, as its body is the plain drill).
const CycleRow& cycle_row(int g) {
  for (const CycleRow& row : kCycles)
    if (row.number10 == g) return row;
  return kCycles[0];
}

// The cycle's L word: how many holes (1 without L).
bool cycle_repeats(BlockCtx& ctx, const std::string& name, int& repeats) {
  const BlockWords& w = ctx.w;
  repeats = 1;
  if (!w.has('L')) return true;
  double l = 0;
  if (!near_integer(w['L']->value, l))
    return ctx.fail(ErrorCode::BadLWord, w['L']->loc,
                    fmt::format("{} L{:g}: L must be an integer", name, w['L']->value));
  if (l <= 0 || l > 1e6)
    return ctx.fail(ErrorCode::BadLWord, w['L']->loc,
                    fmt::format("{} L{:g}: L must be 1 or more (repeats)", name, l));
  repeats = static_cast<int>(l);
  return true;
}

// The spindle as the cycle's rule wants it.
bool cycle_spindle_ok(BlockCtx& ctx, const CycleRow& row, SourceLoc loc, const std::string& name) {
  const int dir = ctx.s.spindle_dir;
  if (row.spindle != SpindleRule::Any && dir == 0)
    return ctx.fail(ErrorCode::CycleMisused, loc,
                    fmt::format("{} with the spindle not turning (M3/M4 first)", name));
  if (row.spindle == SpindleRule::Clockwise && dir < 0)
    return ctx.fail(ErrorCode::CycleMisused, loc,
                    fmt::format("{} with the spindle turning counterclockwise", name));
  if (row.spindle == SpindleRule::Counterclockwise && dir > 0)
    return ctx.fail(ErrorCode::CycleMisused, loc,
                    fmt::format("{} with the spindle turning clockwise", name));
  return true;
}

// The cycle block being run: its row, its axes, where its errors are located, its name.
struct CycleBlock {
  const CycleRow& row;
  CycleAxes ax;
  SourceLoc loc;
  std::string name;
  bool entering;  ///< the first block of a run of this cycle (LinuxCNC: motion_mode != motion)
};

// The checks before anything moves, in this order: rotary words, the hole bottom and R when a
// run of the cycle starts, L, the feed, the row's P, Q and I J K, the spindle.
bool check_cycle(BlockCtx& ctx, const CycleBlock& cb, int& repeats) {
  const ModalState& s = ctx.s;
  const BlockWords& w = ctx.w;
  const std::string& name = cb.name;
  const SourceLoc loc = cb.loc;
  const char cl = kProgramAxisLetters[static_cast<std::size_t>(cb.ax.c)];
  for (const char rot : {'A', 'B', 'C'})
    if (w.has(rot))
      return ctx.fail(
          ErrorCode::CycleMisused, w[rot]->loc,
          fmt::format("{} word in a canned cycle ({}): rotary axes may not move", rot, name));
  if (cb.entering && !w.has(cl))
    return ctx.fail(ErrorCode::MissingWord, loc,
                    fmt::format("{} without {} (the hole bottom) in the {} plane", name, cl,
                                plane_letters(s.plane)));
  if (cb.entering && !w.has('R'))
    return ctx.fail(ErrorCode::MissingWord, loc,
                    fmt::format("{} without R (the retract plane)", name));
  if (!cycle_repeats(ctx, name, repeats)) return false;
  if (s.inverse_time || s.feed_mm_min <= 0.0)
    return ctx.fail(
        ErrorCode::ZeroFeed, loc,
        fmt::format("{} with zero feed rate ({})", name,
                    s.inverse_time ? "G93 gives no feed to a cycle" : "no F yet, or F0"));
  if (cb.entering && cb.row.needs_p && !w.has('P'))
    return ctx.fail(ErrorCode::MissingWord, loc, fmt::format("{} without P (dwell seconds)", name));
  if (cb.entering && cb.row.needs_q && !w.has('Q'))
    return ctx.fail(ErrorCode::MissingWord, loc, fmt::format("{} without Q (peck depth)", name));
  // G87 (back boring): the offset to clear the bore (the plane's two letters of I J K) and the
  // back bore's top (the cycle axis's letter), sticky like R.
  if (cb.row.needs_ijk && cb.entering)
    for (const char l : {'I', 'J', 'K'})
      if (!w.has(l))
        return ctx.fail(ErrorCode::MissingWord, loc,
                        fmt::format("G87 without {} (I J: the offset to pass the bore, K: the "
                                    "back bore's top, in the {} plane's order)",
                                    l, plane_letters(s.plane)));
  return cycle_spindle_ok(ctx, cb.row, loc, name);
}

// The step from one hole to the next: (da, db) in G91, or the polar dr, dtheta.
struct HoleStep {
  double da = 0, db = 0;
  bool polar = false;
  double dr = 0, dtheta = 0;
};

// The first hole (before its step) from the words: P and Q, the place in the plane, the R plane
// and the bottom (from `r_word`, `z_word` and, in G91, the initial level, set here when a run of
// cycle blocks starts), G87's bore; and the step between holes. `here` is the tool's position
// in program units.
bool layout_cycle(BlockCtx& ctx, const CycleBlock& cb, const Pos9& here, double r_word,
                  double z_word, Hole& h, HoleStep& step) {
  ModalState& s = ctx.s;
  const BlockWords& w = ctx.w;
  const CycleAxes ax = cb.ax;
  h.p = w.has('P') ? w['P']->value : s.cycle_p;
  h.q = w.has('Q') ? w['Q']->value : s.cycle_q;
  if (cb.row.needs_q && h.q <= 0.0)
    return ctx.fail(ErrorCode::CycleMisused, w.has('Q') ? w['Q']->loc : cb.loc,
                    fmt::format("{} Q{:g}: the peck depth must be positive", cb.name, h.q));
  // The initial level: the cycle axis where the first cycle block of a run started.
  if (!s.cycle_il_set) {
    s.cycle_il = here[ax.c];
    s.cycle_il_set = true;
  }
  const char la = kProgramAxisLetters[static_cast<std::size_t>(ax.a)];
  const char lb = kProgramAxisLetters[static_cast<std::size_t>(ax.b)];
  h.r = s.incremental ? r_word + s.cycle_il : r_word;
  h.bottom = s.incremental ? h.r + z_word : z_word;
  h.a = s.incremental ? here[ax.a] : w.get(la, here[ax.a]);
  h.b = s.incremental ? here[ax.b] : w.get(lb, here[ax.b]);
  if (s.incremental) {
    step.da = w.get(la);
    step.db = w.get(lb);
  }
  // Polar words (XY plane only, as rs274): G90 places the hole, G91 turns it each repeat.
  step.polar = w.polar.any() && s.plane == Plane::XY;
  if (step.polar) {
    if (w.has('X') || w.has('Y'))
      return ctx.fail(ErrorCode::PolarMisused, w.polar.first()->loc,
                      "polar coordinates (@, ^) cannot be given with X or Y words");
    if (s.incremental) {
      step.dr = w.polar.radius ? w.polar.radius->value : 0.0;
      step.dtheta = w.polar.angle ? w.polar.angle->value : 0.0;
    } else {
      polar_cycle_start(w.polar, h.a, h.b);
    }
  }
  if (h.r < h.bottom)
    return ctx.fail(ErrorCode::CycleMisused, w.has('R') ? w['R']->loc : cb.loc,
                    fmt::format("{}: R ({:g}) below the hole bottom {} ({:g})", cb.name, h.r,
                                kProgramAxisLetters[static_cast<std::size_t>(ax.c)], h.bottom));
  if (cb.row.needs_ijk)
    for (const char l : {'I', 'J', 'K'})
      if (w.has(l)) s.cycle_ijk[static_cast<std::size_t>(l - 'I')] = w[l]->value;
  h.bore_da = s.cycle_ijk[static_cast<std::size_t>(ax.a)];
  h.bore_db = s.cycle_ijk[static_cast<std::size_t>(ax.b)];
  h.bore_top = s.cycle_ijk[static_cast<std::size_t>(ax.c)] +
               (s.incremental ? h.bottom : 0.0);  // G91: from the hole bottom
  return true;
}

}  // namespace

bool run_retract_mode(BlockCtx& ctx, const Code& c) {
  if (!comp_forbids(ctx, ctx.loc_of(Group::ReturnMode), "change the retract mode")) return false;
  ctx.s.retract_to_r = c.number10 == 990;
  return true;
}

// A canned cycle block: checks, lays out the holes, then drills each with the cycle's body
// (LinuxCNC's convert_cycle and convert_cycle_gNN).
bool run_cycle(BlockCtx& ctx, const Code& c) {
  ModalState& s = ctx.s;
  const BlockWords& w = ctx.w;
  const int g = c.number10;
  const SourceLoc loc = w.word_of(Group::Motion) ? w.word_of(Group::Motion)->loc
                        : w.first_axis           ? w.first_axis->loc
                                                 : SourceLoc{ctx.block.line, 1};
  const CycleBlock cb{cycle_row(g), cycle_axes(s.plane), loc, code_name(c), s.cycle_mode != g};
  if (!comp_forbids(ctx, loc, fmt::format("use canned cycle {}", cb.name))) return false;
  int repeats = 1;
  if (!check_cycle(ctx, cb, repeats)) return false;

  const CycleAxes ax = cb.ax;
  const double u = ctx.scale();
  Pos9 here = ctx.frame().to_program(s.position_mm);
  for (int i = 0; i < 3; ++i) here[i] /= u;  // program units
  const char cl = kProgramAxisLetters[static_cast<std::size_t>(ax.c)];
  const double r_word = w.has('R') ? w['R']->value : s.cycle_r;
  const double z_word = w.has(cl) ? w[cl]->value : s.cycle_bottom;
  Hole h;
  HoleStep step;
  if (!layout_cycle(ctx, cb, here, r_word, z_word, h, step)) return false;

  CycleRun run{ctx, ax, loc};
  double old_cc = s.cycle_il;
  double cc = here[ax.c];  // where the cycle axis is now
  if (old_cc < h.r) {      // the initial level is below the R plane: straight up to it first
    if (!run.traverse(here[ax.a], here[ax.b], h.r)) return false;
    old_cc = cc = h.r;
  }
  h.clear = s.retract_to_r ? h.r : old_cc;
  h.peck_back_off = (s.inch ? 1.0 : units::kMmPerInch) * kPeckRapidDeltaInch;
  for (int k = 0; k < repeats; ++k) {
    h.a += step.da;
    h.b += step.db;
    if (std::string why; step.polar && !polar_cycle_step(step.dr, step.dtheta, h.a, h.b, why))
      return ctx.fail(ErrorCode::PolarMisused, w.polar.first()->loc, why);
    // Across above the R plane (where the tool is if above it, else at the clearance height),
    // then down to R (checked against rs274 2.9 output).
    const double across = cc > h.r ? cc : h.clear;
    if (!run.traverse(h.a, h.b, across)) return false;
    if (across != h.r && !run.traverse(h.a, h.b, h.r)) return false;
    if (!cb.row.body(run, h)) return false;
    cc = h.clear;
  }
  s.cycle_r = r_word;
  s.cycle_bottom = z_word;
  if (w.has('P')) s.cycle_p = h.p;
  if (w.has('Q')) s.cycle_q = h.q;
  s.cycle_mode = g;
  return true;
}

}  // namespace gm
