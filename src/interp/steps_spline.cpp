// The spline steps: G5 cubic and G5.1 quadratic splines and G5.2/G5.3 NURBS (LinuxCNC 2.9's
// convert_spline and convert_nurbs), drawn with the biarcs its canon fits (interp/spline.cpp).
#include "interp/steps.hpp"

#include <cmath>
#include <span>
#include <string_view>

namespace gm {

namespace {

constexpr std::size_t kMaxNurbsPoints = 10000;  // 80,000 arcs from one G5.3
constexpr int kMaxNurbsOrder = 32;
constexpr double kStraightTol = 1e-6;  // LinuxCNC draws an arc straight below this (units)
constexpr double kMinWeight = 1e-6, kMaxWeight = 1e6;  // beyond: overflow, not a curve

// A control point (program units) is within the machine's range: the curve stays inside the
// hull of its points, so its pieces do too.
bool point_in_range(BlockCtx& ctx, const ControlPoint& p, SourceLoc loc, std::string_view what) {
  const double u = ctx.scale();
  if (within(p.x * u, kMaxPositionMm) && within(p.y * u, kMaxPositionMm)) return true;
  return ctx.fail(ErrorCode::ValueOutOfRange, loc,
                  fmt::format("{} at ({:g}, {:g}) mm, outside -{:g}..{:g} mm", what, p.x * u,
                              p.y * u, kMaxPositionMm, kMaxPositionMm));
}

// The current point in program units.
ControlPoint here(const BlockCtx& ctx) {
  const Pos9 p = ctx.frame().to_program(ctx.s.position_mm);
  return ControlPoint{p[0] / ctx.scale(), p[1] / ctx.scale(), 1.0};
}

// What every spline refuses: cutter compensation, another plane, inverse time.
bool spline_allowed(BlockCtx& ctx, const Code& c, SourceLoc loc) {
  if (ctx.s.comp.active())
    return ctx.fail(ErrorCode::CutterCompMisused, loc,
                    fmt::format("{} with cutter radius compensation on", code_name(c)));
  if (ctx.s.plane != Plane::XY)
    return ctx.fail(ErrorCode::UnknownGCode, loc,
                    fmt::format("{}: splines must be in the XY plane (G17)", code_name(c)));
  if (ctx.s.inverse_time)
    return ctx.fail(ErrorCode::UnknownGCode, loc,
                    fmt::format("{} in inverse time (G93): LinuxCNC feeds its pieces at the last "
                                "move's rate; use G94",
                                code_name(c)));
  return true;
}

// Emits the fitted pieces (program units) at the current Z and other axes; the last one ends
// exactly on `end_mm`.
bool emit_pieces(BlockCtx& ctx, std::span<const CurvePiece> pieces, const Pos9& end_mm,
                 SourceLoc loc) {
  const double u = ctx.scale();
  const Frame f = ctx.frame();
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const CurvePiece& p = pieces[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y))
      return ctx.fail(ErrorCode::NotANumber, loc, "the spline's points are not finite numbers");
    Pos9 prog = Pos9::Zero();
    prog[0] = p.x * u;
    prog[1] = p.y * u;
    const Pos9 target = i + 1 == pieces.size() ? end_mm : f.to_machine(ctx.s.position_mm, prog, 3u);
    // A nearly straight piece can have its centre far away: beyond the machine's range (a
    // sagitta below chord^2 / 8e12 mm) it is drawn straight.
    if (!p.arc || !within(p.cx * u, kMaxPositionMm) || !within(p.cy * u, kMaxPositionMm)) {
      if (!emit_straight(ctx, MotionKind::Line, target, loc)) return false;
      continue;
    }
    prog[0] = p.cx * u;
    prog[1] = p.cy * u;
    const Pos9 centre = f.to_machine(ctx.s.position_mm, prog, 3u);
    if (!emit_arc(ctx, target, centre, p.ccw)) return false;
  }
  ctx.s.position_mm = end_mm;
  return true;
}

const grammar::Word* first_of(const BlockWords& w, std::string_view letters) {
  for (const char c : letters)
    if (w.has(c)) return w[c];
  return nullptr;
}

}  // namespace

bool run_spline(BlockCtx& ctx, const Code& c) {
  const BlockWords& w = ctx.w;
  const SourceLoc loc =
      w.word_of(Group::Motion) ? w.word_of(Group::Motion)->loc : SourceLoc{ctx.block.line, 1};
  const bool cubic = c.number10 == 50;
  if (!spline_allowed(ctx, c, loc)) return false;
  if (!check_feed(ctx, c.number10, loc)) return false;
  if (const auto* aw = first_of(w, "ZABC"))
    return ctx.fail(ErrorCode::UnusedWord, aw->loc,
                    fmt::format("{}: splines may not move Z, A, B or C", code_name(c)));
  const ControlPoint p0 = here(ctx);
  double i = 0.0, j = 0.0;
  if (w.has('I') && w.has('J')) {
    i = w['I']->value;
    j = w['J']->value;
  } else if (!cubic || w.has('I') || w.has('J')) {
    return ctx.fail(ErrorCode::MissingWord, loc,
                    cubic ? "G5 needs both I and J, or neither (then the last G5's -P -Q)"
                          : "G5.1 needs both I and J");
  } else {  // G5 without I J: LinuxCNC's stored cycle I J (the last G5's -P -Q, or G87's)
    i = ctx.s.cycle_ijk[0];
    j = ctx.s.cycle_ijk[1];
  }
  if (cubic && !(w.has('P') && w.has('Q')))
    return ctx.fail(ErrorCode::MissingWord, loc, "G5 needs both P and Q");
  Pos9 end;
  if (!axis_target(ctx, ctx.s.position_mm, end)) return false;
  const Pos9 end_p = ctx.frame().to_program(end);
  const ControlPoint p3{end_p[0] / ctx.scale(), end_p[1] / ctx.scale(), 1.0};
  std::array<ControlPoint, 4> pts{};
  pts[0] = p0;
  pts[1] = ControlPoint{p0.x + i, p0.y + j, 1.0};
  std::size_t n = 3;
  if (cubic) {
    pts[2] = ControlPoint{p3.x + w['P']->value, p3.y + w['Q']->value, 1.0};
    pts[3] = p3;
    n = 4;
    ctx.s.cycle_ijk[0] = -w['P']->value;
    ctx.s.cycle_ijk[1] = -w['Q']->value;
  } else {
    pts[2] = p3;
  }
  for (std::size_t k = 1; k + 1 < n; ++k)
    if (!point_in_range(ctx, pts[k], loc, fmt::format("{}'s control point", code_name(c))))
      return false;
  std::vector<CurvePiece> pieces;
  nurbs_biarcs(std::span<const ControlPoint>(pts.data(), n), static_cast<int>(n), kStraightTol,
               pieces);
  return emit_pieces(ctx, pieces, end, loc);
}

bool run_nurbs_point(BlockCtx& ctx, const Code& c) {
  const BlockWords& w = ctx.w;
  const SourceLoc loc = w.word_of(Group::Motion) ? w.word_of(Group::Motion)->loc
                        : w.first_axis           ? w.first_axis->loc
                                                 : SourceLoc{ctx.block.line, 1};
  if (!spline_allowed(ctx, c, loc)) return false;
  const bool fresh = ctx.motion_before != 52;  // a new curve (LinuxCNC clears its list)
  NurbsEdit& e = ctx.nurbs_edit;
  e.clear = fresh;
  const std::size_t have = fresh ? 0 : ctx.nurbs->points.size();
  const bool xy = w.has('X') && w.has('Y');
  if (w.has('X') != w.has('Y'))
    return ctx.fail(ErrorCode::MissingWord, loc, "G5.2: a control point needs both X and Y");
  const double p = w.has('P') ? w['P']->value : -1.0;
  if (!xy && w.has('P') && p > 0.0 && have > 0)
    return ctx.fail(ErrorCode::MissingWord, w['P']->loc,
                    "G5.2: P without X and Y sets the weight of the first control point only");
  if (have > 0 && p <= 0.0)
    return ctx.fail(ErrorCode::MissingWord, w.has('P') ? w['P']->loc : loc,
                    "G5.2: every control point needs a positive weight P");
  if (xy && p <= 0.0)  // LinuxCNC would give this first point the weight -1 (P's default)
    return ctx.fail(ErrorCode::MissingWord, w.has('P') ? w['P']->loc : loc,
                    "G5.2: the control point needs a positive weight P");
  if (w.has('P') && p > 0.0 && !(p >= kMinWeight && p <= kMaxWeight))
    return ctx.fail(ErrorCode::ValueOutOfRange, w['P']->loc,
                    fmt::format("G5.2 P{:g}: a weight must be between {:g} and {:g}", p, kMinWeight,
                                kMaxWeight));
  if (!ctx.s.per_rev && ctx.s.feed_mm_min <= 0.0)
    return ctx.fail(ErrorCode::ZeroFeed, loc, "G5.2: cannot make a NURBS with zero feed rate");
  if (have + 2 > kMaxNurbsPoints)
    return ctx.fail(ErrorCode::ValueOutOfRange, loc,
                    fmt::format("G5.2: more than {} control points in one curve", kMaxNurbsPoints));
  if (have == 0) {  // the first point: where the curve starts
    ControlPoint first = here(ctx);
    if (!xy && p > 0.0) first.w = p;
    e.add[static_cast<std::size_t>(e.added++)] = first;
    e.order = 3;
  }
  if (w.has('L')) {
    double l = 0.0;
    if (!near_integer(w['L']->value, l) || l > kMaxNurbsOrder)
      return ctx.fail(ErrorCode::BadLWord, w['L']->loc,
                      fmt::format("G5.2 L{:g}: the order must be an integer up to {}",
                                  w['L']->value, kMaxNurbsOrder));
    if (l > 3) e.order = static_cast<int>(l);  // LinuxCNC ignores L3 and below
  }
  if (xy) {
    // The point as an end point (G90/G91 from where the curve started, polar words).
    Pos9 end;
    if (!axis_target(ctx, ctx.s.position_mm, end)) return false;
    const Pos9 q = ctx.frame().to_program(end);
    e.add[static_cast<std::size_t>(e.added++)] =
        ControlPoint{q[0] / ctx.scale(), q[1] / ctx.scale(), p};
  }
  return true;
}

bool run_nurbs_end(BlockCtx& ctx, const Code& c) {
  const SourceLoc loc = ctx.w.word_of(Group::Motion)->loc;
  if (ctx.motion_before != 52)
    return ctx.fail(ErrorCode::MissingWord, loc, "G5.3 without G5.2 first");
  const std::vector<ControlPoint>& pts = ctx.nurbs->points;
  const int order = ctx.nurbs->order;
  if (pts.size() < static_cast<std::size_t>(order))
    return ctx.fail(ErrorCode::MissingWord, loc,
                    fmt::format("G5.3: the curve has {} control points, fewer than its order L{}",
                                pts.size(), order));
  if (!spline_allowed(ctx, c, loc)) return false;
  std::vector<CurvePiece> pieces;
  nurbs_biarcs(pts, order, kStraightTol, pieces);
  Pos9 last = Pos9::Zero();
  last[0] = pts.back().x * ctx.scale();
  last[1] = pts.back().y * ctx.scale();
  const Pos9 end = ctx.frame().to_machine(ctx.s.position_mm, last, 3u);
  if (!emit_pieces(ctx, pieces, end, loc)) return false;
  ctx.nurbs_edit.clear = true;
  ctx.s.motion = -1;  // LinuxCNC: no motion mode after G5.3
  return true;
}

}  // namespace gm
