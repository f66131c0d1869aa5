// Canned cycles G73, G74, G81..G86, G89 with G98/G99, R, L, P, Q, incremental mode and every
// plane, expanded into moves as LinuxCNC 2.9 expands them (interp_cycles.cc semantics).
#include "interp/steps.hpp"

#include <cmath>

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

}  // namespace

bool run_retract_mode(BlockCtx& ctx, const Code& c) {
  if (!comp_forbids(ctx, ctx.loc_of(Group::ReturnMode), "change the retract mode")) return false;
  ctx.s.retract_to_r = c.number10 == 990;
  return true;
}

bool run_cycle(BlockCtx& ctx, const Code& c) {
  ModalState& s = ctx.s;
  const BlockWords& w = ctx.w;
  const int g = c.number10;
  const SourceLoc loc = w.word_of(Group::Motion) ? w.word_of(Group::Motion)->loc
                        : w.first_axis           ? w.first_axis->loc
                                                 : SourceLoc{ctx.block.line, 1};
  const std::string name = code_name(c);
  if (!comp_forbids(ctx, loc, fmt::format("use canned cycle {}", name))) return false;
  const bool entering = s.cycle_mode != g;  // LinuxCNC: motion_mode != motion
  const CycleAxes ax = cycle_axes(s.plane);
  const char cl = kProgramAxisLetters[static_cast<std::size_t>(ax.c)];

  for (const char rot : {'A', 'B', 'C'})
    if (w.has(rot))
      return ctx.fail(
          ErrorCode::CycleMisused, w[rot]->loc,
          fmt::format("{} word in a canned cycle ({}): rotary axes may not move", rot, name));
  if (entering && !w.has(cl))
    return ctx.fail(ErrorCode::MissingWord, loc,
                    fmt::format("{} without {} (the hole bottom) in the {} plane", name, cl,
                                plane_letters(s.plane)));
  if (entering && !w.has('R'))
    return ctx.fail(ErrorCode::MissingWord, loc,
                    fmt::format("{} without R (the retract plane)", name));
  int repeats = 1;
  if (w.has('L')) {
    double l = 0;
    if (!near_integer(w['L']->value, l))
      return ctx.fail(ErrorCode::BadLWord, w['L']->loc,
                      fmt::format("{} L{:g}: L must be an integer", name, w['L']->value));
    if (l <= 0 || l > 1e6)
      return ctx.fail(ErrorCode::BadLWord, w['L']->loc,
                      fmt::format("{} L{:g}: L must be 1 or more (repeats)", name, l));
    repeats = static_cast<int>(l);
  }
  if (s.inverse_time || s.feed_mm_min <= 0.0)
    return ctx.fail(
        ErrorCode::ZeroFeed, loc,
        fmt::format("{} with zero feed rate ({})", name,
                    s.inverse_time ? "G93 gives no feed to a cycle" : "no F yet, or F0"));
  const bool needs_p = g == 820 || g == 860 || g == 880 || g == 890;
  const bool needs_q = g == 730 || g == 830;
  if (entering && needs_p && !w.has('P'))
    return ctx.fail(ErrorCode::MissingWord, loc, fmt::format("{} without P (dwell seconds)", name));
  if (entering && needs_q && !w.has('Q'))
    return ctx.fail(ErrorCode::MissingWord, loc, fmt::format("{} without Q (peck depth)", name));
  // G87 (back boring): the offset to clear the bore (the plane's two letters of I J K) and the
  // back bore's top (the cycle axis's letter), sticky like R.
  const char off_a = "IJK"[ax.a], off_b = "IJK"[ax.b], top = "IJK"[ax.c];
  if (g == 870 && entering)
    for (const char l : {'I', 'J', 'K'})
      if (!w.has(l))
        return ctx.fail(ErrorCode::MissingWord, loc,
                        fmt::format("G87 without {} (I J: the offset to pass the bore, K: the "
                                    "back bore's top, in the {} plane's order)",
                                    l, plane_letters(s.plane)));
  if ((g == 740 || g == 840 || g == 860 || g == 870 || g == 880) && s.spindle_dir == 0)
    return ctx.fail(ErrorCode::CycleMisused, loc,
                    fmt::format("{} with the spindle not turning (M3/M4 first)", name));
  if (g == 840 && s.spindle_dir < 0)
    return ctx.fail(ErrorCode::CycleMisused, loc, "G84 with the spindle turning counterclockwise");
  if (g == 740 && s.spindle_dir > 0)
    return ctx.fail(ErrorCode::CycleMisused, loc, "G74 with the spindle turning clockwise");

  const double u = ctx.scale();
  const Pos9 here = ctx.frame().to_program(s.position_mm);
  auto prog = [&](int i) { return here[i] / u; };
  const double r_word = w.has('R') ? w['R']->value : s.cycle_r;
  const double z_word = w.has(cl) ? w[cl]->value : s.cycle_bottom;
  const double p = w.has('P') ? w['P']->value : s.cycle_p;
  const double q = w.has('Q') ? w['Q']->value : s.cycle_q;
  if (needs_q && q <= 0.0)
    return ctx.fail(ErrorCode::CycleMisused, w.has('Q') ? w['Q']->loc : loc,
                    fmt::format("{} Q{:g}: the peck depth must be positive", name, q));

  // The initial level: the cycle axis where the first cycle block of a run started.
  if (!s.cycle_il_set) {
    s.cycle_il = prog(ax.c);
    s.cycle_il_set = true;
  }
  double old_cc = s.cycle_il;
  double a = prog(ax.a), b = prog(ax.b), r = 0, bottom = 0, da = 0, db = 0;
  const char la = kProgramAxisLetters[static_cast<std::size_t>(ax.a)];
  const char lb = kProgramAxisLetters[static_cast<std::size_t>(ax.b)];
  if (s.incremental) {
    da = w.get(la);
    db = w.get(lb);
    r = r_word + old_cc;
    bottom = r + z_word;
  } else {
    a = w.get(la, a);
    b = w.get(lb, b);
    r = r_word;
    bottom = z_word;
  }
  // Polar words (XY plane only, as rs274): G90 places the hole, G91 turns it each repeat.
  double dr = 0, dtheta = 0;
  const bool polar = w.polar.any() && s.plane == Plane::XY;
  if (polar) {
    if (w.has('X') || w.has('Y'))
      return ctx.fail(ErrorCode::PolarMisused, w.polar.first()->loc,
                      "polar coordinates (@, ^) cannot be given with X or Y words");
    if (s.incremental) {
      dr = w.polar.radius ? w.polar.radius->value : 0.0;
      dtheta = w.polar.angle ? w.polar.angle->value : 0.0;
    } else {
      polar_cycle_start(w.polar, a, b);
    }
  }
  if (r < bottom)
    return ctx.fail(
        ErrorCode::CycleMisused, w.has('R') ? w['R']->loc : loc,
        fmt::format("{}: R ({:g}) below the hole bottom {} ({:g})", name, r, cl, bottom));

  CycleRun run{ctx, ax, loc};
  double cc = prog(ax.c);  // where the cycle axis is now
  if (g == 870) {
    for (const char l : {'I', 'J', 'K'})
      if (w.has(l)) s.cycle_ijk[static_cast<std::size_t>(l - 'I')] = w[l]->value;
  }
  const double bore_da = s.cycle_ijk[static_cast<std::size_t>(off_a - 'I')];
  const double bore_db = s.cycle_ijk[static_cast<std::size_t>(off_b - 'I')];
  const double bore_top = s.cycle_ijk[static_cast<std::size_t>(top - 'I')] +
                          (s.incremental ? bottom : 0.0);  // G91: from the hole bottom
  if (old_cc < r) {  // the initial level is below the R plane: straight up to it first
    if (!run.traverse(prog(ax.a), prog(ax.b), r)) return false;
    old_cc = cc = r;
  }
  const double clear = s.retract_to_r ? r : old_cc;
  const double delta = (s.inch ? 1.0 : 25.4) * kPeckRapidDeltaInch;
  for (int k = 0; k < repeats; ++k) {
    a += da;
    b += db;
    if (std::string why; polar && !polar_cycle_step(dr, dtheta, a, b, why))
      return ctx.fail(ErrorCode::PolarMisused, w.polar.first()->loc, why);
    // Across above the R plane (where the tool is if above it, else at the clearance height),
    // then down to R (checked against rs274 2.9 output).
    const double across = cc > r ? cc : clear;
    if (!run.traverse(a, b, across)) return false;
    if (across != r && !run.traverse(a, b, r)) return false;
    bool ok = true;
    switch (g) {
      case 730:  // chip break: feed a peck, back off a little
      case 830:  // peck: feed a peck, out to R, back down to just above the last depth
        for (double depth = r - q; ok && depth > bottom; depth -= q) {
          ok = run.feed(a, b, depth) && (g == 730 || run.traverse(a, b, r)) &&
               run.traverse(a, b, depth + delta);
        }
        ok = ok && run.feed(a, b, bottom) && run.traverse(a, b, clear);
        break;
      case 740:  // tapping: feed in, spindle reverses, dwell, feed out, spindle as it was
      case 840:
        ok = run.feed(a, b, bottom);
        if (ok) {
          run.spindle(-s.spindle_dir);
          run.dwell(p);
        }
        ok = ok && run.feed(a, b, clear);
        if (ok) run.spindle(s.spindle_dir);
        break;
      case 820:  // feed in, dwell, rapid out
      case 860:  // as G82 with the spindle stopped on the way out
        ok = run.feed(a, b, bottom);
        if (ok) run.dwell(p);
        if (ok && g == 860) run.spindle(0);
        ok = ok && run.traverse(a, b, clear);
        if (ok && g == 860) emit_io(ctx, EventKind::SpindleStart, s.spindle_dir, s.spindle_rpm);
        break;
      case 870: {  // back boring: down beside the bore with the spindle oriented, centre, cut
                   // up to the top and back, orient again, out beside the bore, centre at clear
        const double oa = a + bore_da, ob = b + bore_db;
        const auto orient = [&] {
          run.spindle(0);
          emit_io(ctx, EventKind::SpindleOrient, s.spindle_dir > 0 ? 2 : 3, 0.0);
        };
        ok = run.traverse(oa, ob, r);
        if (ok) orient();
        ok = ok && run.traverse(oa, ob, bottom) && run.traverse(a, b, bottom);
        if (ok) emit_io(ctx, EventKind::SpindleStart, s.spindle_dir, s.spindle_rpm);
        ok = ok && run.feed(a, b, bore_top) && run.feed(a, b, bottom);
        if (ok) orient();
        ok = ok && run.traverse(oa, ob, bottom) && run.traverse(oa, ob, clear) &&
             run.traverse(a, b, clear);
        if (ok) emit_io(ctx, EventKind::SpindleStart, s.spindle_dir, s.spindle_rpm);
        break;
      }
      case 880:  // feed in, dwell, spindle off, program stop: the operator retracts by hand to
                 // the clearance height (where LinuxCNC's interpreter then takes the tool to
                 // be), spindle on again
        ok = run.feed(a, b, bottom);
        if (ok) {
          run.dwell(p);
          run.spindle(0);
          run.program_stop();
        }
        ok = ok && run.operator_retract(a, b, clear);
        if (ok) emit_io(ctx, EventKind::SpindleStart, s.spindle_dir, s.spindle_rpm);
        break;
      case 850:  // feed in, feed out to R, rapid to clear
        ok = run.feed(a, b, bottom) && run.feed(a, b, r) && run.traverse(a, b, clear);
        break;
      case 890:  // feed in, dwell, feed out to clear
        ok = run.feed(a, b, bottom);
        if (ok) run.dwell(p);
        ok = ok && run.feed(a, b, clear);
        break;
      default:  // 810: feed in, rapid out
        ok = run.feed(a, b, bottom) && run.traverse(a, b, clear);
        break;
    }
    if (!ok) return false;
    cc = clear;
  }
  s.cycle_r = r_word;
  s.cycle_bottom = z_word;
  if (w.has('P')) s.cycle_p = p;
  if (w.has('Q')) s.cycle_q = q;
  s.cycle_mode = g;
  return true;
}

}  // namespace gm
