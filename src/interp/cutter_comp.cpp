// Cutter radius compensation with LinuxCNC 2.9's rules (semantics of interp_convert.cc
// convert_*_comp1/comp2 and interp_queue.cc, rewritten): the entry move puts the tool one radius
// to the side at its end; each later move is offset by the radius; a convex corner gets an arc
// around the programmed corner point, a concave corner moves the end of the held-back previous
// move to where the tool touches both elements; G40 lets the held-back move end where it is.
// Geometry is done in the plane's two axes (a, b) = plane_axes(): X,Y for G17, Z,X for G18.
#include "interp/cutter_comp.hpp"

#include "common/units.hpp"
#include "interp/steps.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iterator>
#include <numbers>

namespace gm {

CompQueue& CompQueue::operator=(const CompQueue& o) {
  if (this == &o) return *this;
  std::size_t keep = std::min(ids_.size(), o.ids_.size());
  if (keep > 0 && ids_[keep - 1] != o.ids_[keep - 1]) keep = 0;
  const auto k = static_cast<std::ptrdiff_t>(keep);
  items_.erase(items_.begin() + k, items_.end());
  ids_.erase(ids_.begin() + k, ids_.end());
  items_.insert(items_.end(), o.items_.begin() + k, o.items_.end());
  ids_.insert(ids_.end(), o.ids_.begin() + k, o.ids_.end());
  return *this;
}

void CompQueue::push_back(CompQueued q) {
  static std::atomic<std::uint64_t> pushes{0};
  items_.push_back(std::move(q));
  ids_.push_back(pushes.fetch_add(1, std::memory_order_relaxed) + 1);
}

namespace {

constexpr double kPi = std::numbers::pi;
// LinuxCNC interp_internal.hh: TOLERANCE_CONCAVE_CORNER (radians), TOLERANCE_EQUAL.
constexpr double kCornerTolRad = 0.05;
constexpr double kEqualTol = 1e-6;
// interp_queue.cc: a concave corner may lengthen a held-back arc by this much sweep before it is
// a gouge; the number is compared with radians and is 0.0254 under G21 and 0.001 under G20.
constexpr double kSweepSlackMm = 0.0254, kSweepSlackInch = 0.001;
// Commands held back at once (moves along the normal axis, dwells): a bound for untrusted input.
constexpr std::size_t kMaxQueued = 10000;

struct P2 {
  double a = 0.0, b = 0.0;
};
bool operator==(P2 p, P2 q) {
  return p.a == q.a && p.b == q.b;
}
double angle(P2 from, P2 to) {
  return std::atan2(to.b - from.b, to.a - from.a);
}
double dist(P2 p, P2 q) {
  return std::hypot(q.a - p.a, q.b - p.b);
}
P2 polar(P2 o, double r, double t) {
  return {o.a + r * std::cos(t), o.b + r * std::sin(t)};
}
P2 in_plane(const Pos9& p, PlaneAxes ax) {
  return {p[ax.a], p[ax.b]};
}
Pos9 with_plane(Pos9 p, PlaneAxes ax, P2 q) {
  p[ax.a] = q.a;
  p[ax.b] = q.b;
  return p;
}
// Signed sweep from s to e around c (LinuxCNC find_turn): turn > 0 counter-clockwise, the end is
// moved by a turn when it is not beyond the start, each further turn adds 2 pi.
double sweep(P2 s, P2 c, int turn, P2 e) {
  if (turn == 0) return 0.0;
  double a0 = angle(c, s), a1 = angle(c, e);
  if (turn > 0) {
    if (a1 <= a0) a1 += 2 * kPi;
    return a1 - a0 + (turn - 1) * 2 * kPi;
  }
  if (a0 <= a1) a0 += 2 * kPi;
  return a1 - a0 + (turn + 1) * 2 * kPi;
}
int turn_of(const Motion& m) {
  return m.ccw ? m.turns : -m.turns;
}
// The tool is inside an arc of sense `turn` (LinuxCNC TOOL_INSIDE_ARC).
bool inside(int side, int turn) {
  return side * turn > 0;
}

SourceLoc block_loc(const BlockCtx& ctx) {
  if (const auto* mw = ctx.w.word_of(Group::Motion)) return mw->loc;
  if (ctx.w.first_axis) return ctx.w.first_axis->loc;
  return SourceLoc{ctx.block.line, 1};
}

// A lathe tool's controlled point is not its nose centre: LinuxCNC shifts what leaves the queue
// in G18 by the radius according to the orientation (interp_queue.cc latheorigin_x/z).
void lathe_origin(const CutterComp& cc, Plane plane, Pos9& p) {
  if (plane != Plane::XZ) return;
  const int o = cc.orientation;
  const double r = cc.radius_mm;
  if (o == 2 || o == 6 || o == 1) p[0] -= r;
  if (o == 3 || o == 8 || o == 4) p[0] += r;
  if (o == 2 || o == 7 || o == 3) p[2] -= r;
  if (o == 1 || o == 5 || o == 4) p[2] += r;
}

// Sends the held-back commands on (LinuxCNC dequeue_canons); with `moved_end`, every held-back
// move ends there in the plane instead.
void dequeue(BlockCtx& ctx, const P2* moved_end = nullptr) {
  CutterComp& cc = ctx.s.comp;
  cc.end_valid = false;
  for (const CompQueued& q : cc.queue) {
    if (!q.is_motion) {
      ctx.out.push_back(q.held);
      continue;
    }
    Motion mo = q.mo;
    Pos9 end = q.end_mm, centre = q.center_mm;
    if (moved_end != nullptr) end = with_plane(end, plane_axes(ctx.s.plane), *moved_end);
    lathe_origin(cc, mo.plane, end);
    const Pos9 start = cc.emitted_mm;
    mo.start_mm = to_machine(start, ctx.machine.layout);
    mo.end_mm = to_machine(end, ctx.machine.layout);
    if (mo.kind == MotionKind::Arc) {
      lathe_origin(cc, mo.plane, centre);
      centre[plane_axes(mo.plane).n] = start[plane_axes(mo.plane).n];
      mo.center_mm = to_machine(centre, ctx.machine.layout);
    }
    cc.emitted_mm = end;
    if (mo.kind != MotionKind::Arc && mo.end_mm == mo.start_mm) continue;  // as emit_straight
    if (mo.mm_per_rev > 0.0)  // G95: the feed where this (compensated) move starts
      mo.feed_mm_min = mo.mm_per_rev * mo.spindle_rpm_at(mo.start_mm[0]);
    if (q.inverse_time && mo.feed_mm_min > 0.0)
      mo.inverse_time_s = units::kSecondsPerMinute * motion_length_mm(mo) / mo.feed_mm_min;
    ctx.out.emplace_back(mo);
  }
  cc.queue.clear();
}

void set_endpoint(CutterComp& cc, P2 p) {
  cc.end_a = p.a;
  cc.end_b = p.b;
  cc.end_valid = true;
}

bool enqueue(BlockCtx& ctx, CompQueued q) {
  if (ctx.s.comp.queue.size() >= kMaxQueued)
    return ctx.fail(
        ErrorCode::CutterCompMisused, block_loc(ctx),
        fmt::format("more than {} moves without motion in the compensation plane", kMaxQueued));
  ctx.s.comp.queue.push_back(std::move(q));
  return true;
}

// Moves the end of every held-back move to `p` and sends them on; a move that would have to run
// backwards (or an arc that would sweep further) is a gouge (LinuxCNC move_endpoint_and_flush).
bool move_end_and_flush(BlockCtx& ctx, P2 p) {
  CutterComp& cc = ctx.s.comp;
  if (cc.queue.empty()) return true;
  const PlaneAxes ax = plane_axes(ctx.s.plane);
  const P2 from{cc.end_a, cc.end_b};
  for (const CompQueued& q : cc.queue) {
    if (!q.is_motion) continue;
    if (q.mo.kind == MotionKind::Arc) {
      const P2 c = in_plane(q.center_mm, ax);
      const double r1 = dist(c, in_plane(q.end_mm, ax)), r2 = dist(c, p);
      const double new_sweep = sweep(from, c, turn_of(q.mo), p);
      const double slack = ctx.s.inch ? kSweepSlackInch : kSweepSlackMm;
      if (std::fabs(r1 - r2) > 0.01 * ctx.scale())
        return ctx.fail(ErrorCode::CompGouge, block_loc(ctx),
                        fmt::format("cutter compensation made an arc with radii {:.4f} and {:.4f} "
                                    "mm (internal error)",
                                    r1, r2));
      if (q.sweep_rad != 0.0 && cc.end_valid &&
          std::fabs(new_sweep) > std::fabs(q.sweep_rad) + slack)
        return ctx.fail(ErrorCode::CompGouge, block_loc(ctx),
                        "arc move in concave corner cannot be reached by the tool without gouging");
    } else {
      const double dot = q.dir_a * (p.a - from.a) + q.dir_b * (p.b - from.b);
      if (cc.end_valid && dot < 0)
        return ctx.fail(
            ErrorCode::CompGouge, block_loc(ctx),
            fmt::format("straight {} in concave corner cannot be reached by the tool "
                        "without gouging (line {} would run backwards)",
                        q.mo.kind == MotionKind::Rapid ? "traverse" : "feed", q.mo.line));
    }
  }
  dequeue(ctx, &p);
  set_endpoint(cc, p);
  return true;
}

// Feed of this block's compensated moves: G94 the modal feed; G93 the rate that makes the
// programmed (uncompensated) path take 1/F minutes (LinuxCNC inverse_time_rate_*), false with
// the error where it is out of range.
bool block_feed(BlockCtx& ctx, double programmed_len_mm, double& feed) {
  feed = ctx.s.feed_mm_min;
  return !ctx.s.inverse_time || inverse_time_feed(ctx, programmed_len_mm, feed);
}

CompQueued straight_item(const BlockCtx& ctx, MotionKind kind, const Pos9& end, double feed,
                         double dir_a, double dir_b) {
  CompQueued q;
  q.mo = motion_template(ctx, kind);
  q.mo.feed_mm_min = kind == MotionKind::Rapid ? 0.0 : feed;
  if (kind != MotionKind::Rapid && ctx.s.per_rev) set_spindle_feed(ctx, q.mo, ctx.s.feed_mm_min);
  q.inverse_time = kind != MotionKind::Rapid && ctx.s.inverse_time;
  q.end_mm = end;
  q.dir_a = dir_a;
  q.dir_b = dir_b;
  return q;
}

CompQueued arc_item(const BlockCtx& ctx, const Pos9& end, const Pos9& centre, int turn, double feed,
                    double sweep_rad) {
  CompQueued q;
  q.mo = motion_template(ctx, MotionKind::Arc);
  q.mo.feed_mm_min = feed;
  if (ctx.s.per_rev) set_spindle_feed(ctx, q.mo, ctx.s.feed_mm_min);
  q.mo.ccw = turn > 0;
  q.mo.turns = std::abs(turn);
  q.inverse_time = ctx.s.inverse_time;
  q.end_mm = end;
  q.center_mm = centre;
  q.sweep_rad = sweep_rad;
  return q;
}

bool front_is_arc(const CutterComp& cc) {
  return !cc.queue.empty() && cc.queue.front().is_motion &&
         cc.queue.front().mo.kind == MotionKind::Arc;
}

bool tool_too_large(BlockCtx& ctx, std::string what, double len_mm) {
  return ctx.fail(ErrorCode::CompToolTooLarge, block_loc(ctx),
                  fmt::format("{} ({:.6g} mm) is not greater than the tool radius ({:.6g} mm)",
                              what, len_mm, ctx.s.comp.radius_mm));
}

bool gouge(BlockCtx& ctx, std::string_view what) {
  return ctx.fail(ErrorCode::CompGouge, block_loc(ctx),
                  fmt::format("{} makes a corner the compensated tool cannot fit in without "
                              "gouging",
                              what));
}

// The corner arc around the programmed point `o` from the tool's point to `mid` (convex
// corners): the normal axis stays, the other axes make their whole move on it (LinuxCNC).
bool corner_move(BlockCtx& ctx, MotionKind kind, P2 o, P2 mid, const Pos9& target, double feed) {
  CutterComp& cc = ctx.s.comp;
  const PlaneAxes ax = plane_axes(ctx.s.plane);
  Pos9 end = with_plane(target, ax, mid);
  end[ax.n] = ctx.s.position_mm[ax.n];
  if (kind == MotionKind::Arc || kind == MotionKind::Line) {
    if (!enqueue(ctx, arc_item(ctx, end, with_plane(end, ax, o), -cc.side, feed, 0.0)))
      return false;
  } else if (!enqueue(ctx, straight_item(ctx, MotionKind::Rapid, end, 0.0, 0.0, 0.0))) {
    return false;
  }
  dequeue(ctx);
  set_endpoint(cc, mid);
  return true;
}

}  // namespace

Pos9 comp_program_point(const BlockCtx& ctx) {
  const CutterComp& cc = ctx.s.comp;
  if (!cc.on() || cc.first_move) return ctx.s.position_mm;
  return with_plane(ctx.s.position_mm, plane_axes(ctx.s.plane), {cc.prog_a, cc.prog_b});
}

const Pos9& motion_start(const BlockCtx& ctx) {
  return ctx.s.comp.detached ? ctx.s.comp.emitted_mm : ctx.s.position_mm;
}

void emit_in_order(BlockCtx& ctx, Canon c) {
  if (ctx.s.comp.queue.empty() || std::holds_alternative<Motion>(c)) {
    ctx.out.push_back(std::move(c));
    return;
  }
  CompQueued q;
  q.is_motion = false;
  q.held = std::move(c);
  if (ctx.s.comp.queue.size() < kMaxQueued)
    ctx.s.comp.queue.push_back(std::move(q));
  else
    ctx.out.push_back(std::move(q.held));
}

bool comp_forbids(BlockCtx& ctx, SourceLoc loc, std::string_view what) {
  if (!ctx.s.comp.on()) return true;
  return ctx.fail(ErrorCode::CutterCompMisused, loc,
                  fmt::format("cannot {} with cutter radius compensation on (G40 first)", what));
}

bool comp_flush(BlockCtx& ctx) {
  const PlaneAxes ax = plane_axes(ctx.s.plane);
  return move_end_and_flush(ctx, in_plane(ctx.s.position_mm, ax));
}

namespace {

// G40: the held-back move ends where the tool is; compensation is off.
bool comp_off(BlockCtx& ctx) {
  CutterComp& cc = ctx.s.comp;
  if (cc.active() && !cc.first_move) {
    const PlaneAxes ax = plane_axes(ctx.s.plane);
    if (!move_end_and_flush(ctx, in_plane(ctx.s.position_mm, ax))) return false;
    ctx.s.position_mm = with_plane(ctx.s.position_mm, ax, {cc.prog_a, cc.prog_b});
    cc.detached = true;
    cc.arc_not_allowed = true;
  }
  cc.side = 0;
  cc.first_move = true;
  return true;
}

// G41/G42 [D<tool>]: the radius and orientation of the tool table's tool D (no D: the tool in
// the spindle).
bool comp_tool_radius(BlockCtx& ctx, SourceLoc loc, const std::string& name, double& radius_mm,
                      int& orientation) {
  const auto* dw = ctx.w['D'];
  int tool = ctx.s.spindle_slot_tool;
  if (dw) {
    double t = 0;
    if (std::fabs(dw->value - std::round(dw->value)) >= 0.0001)
      return ctx.fail(ErrorCode::CutterCompMisused, dw->loc,
                      fmt::format("{} D{:g}: D must be a whole number (a tool)", name, dw->value));
    t = std::round(dw->value);
    if (t < 0)
      return ctx.fail(ErrorCode::NegativeValue, dw->loc,
                      fmt::format("{} D{:g}: negative tool number", name, dw->value));
    if (t > kMaxToolNumber || (t != 0 && !ctx.tables().tools.find(static_cast<int>(t))))
      return ctx.fail(ErrorCode::ToolNumberOutOfRange, dw->loc,
                      fmt::format("{} D{:g}: tool {:g} is not in the tool table ({})", name, t, t,
                                  ctx.tables().tools.source));
    if (t != 0) tool = static_cast<int>(t);
  }
  if (const ToolEntry* e = tool == 0 ? nullptr : ctx.tables().tools.find(tool)) {
    radius_mm = e->diameter_mm / 2.0;
    orientation = e->orientation;
  }
  if (ctx.s.plane != Plane::XZ && orientation != 0 && orientation != 9)
    return ctx.fail(
        ErrorCode::CutterCompMisused, loc,
        fmt::format("{} with a lathe tool (orientation {}) outside G18", name, orientation));
  return true;
}

}  // namespace

bool run_cutter_comp(BlockCtx& ctx, const Code& c) {
  CutterComp& cc = ctx.s.comp;
  const SourceLoc loc = ctx.loc_of(Group::CutterComp);
  const std::string name = code_name(c);
  if (c.number10 == 400) return comp_off(ctx);
  if (ctx.s.plane == Plane::YZ)
    return ctx.fail(ErrorCode::CutterCompMisused, loc,
                    fmt::format("{}: cutter radius compensation works in the XY (G17) and XZ (G18) "
                                "planes only",
                                name));
  if (cc.on() && !cc.reissue)
    return ctx.fail(ErrorCode::CutterCompMisused, loc,
                    fmt::format("{}: cutter radius compensation is already on", name));
  if (cc.on() && !comp_off(ctx)) return false;  // Fanuc: started again with the new D
  int side = c.number10 / 10 == 41 ? 1 : -1;
  double radius_mm = 0.0;
  int orientation = 0;
  if (c.number10 % 10 == 1) {  // G41.1/G42.1 D<diameter> [L<orientation>]
    const auto* dw = ctx.w['D'];
    if (!dw)
      return ctx.fail(ErrorCode::CutterCompMisused, loc,
                      fmt::format("{} without D (the tool diameter)", name));
    radius_mm = dw->value * ctx.scale() / 2.0;
    if (const auto* lw = ctx.w['L']) {
      if (ctx.s.plane != Plane::XZ)
        return ctx.fail(ErrorCode::CutterCompMisused, lw->loc,
                        fmt::format("{} with L (lathe tool orientation) outside G18", name));
      orientation = static_cast<int>(lw->value);
    }
  } else if (!comp_tool_radius(ctx, loc, name, radius_mm, orientation)) {
    return false;
  }
  if (radius_mm < 0.0) {  // a negative diameter: the other side with the positive radius
    radius_mm = -radius_mm;
    side = -side;
  }
  cc.side = side;
  cc.radius_mm = radius_mm;
  cc.orientation = orientation;
  cc.first_move = true;
  return true;
}

namespace {

// The entry move from the tool at `c`: ends one radius to the side of the programmed end `p`.
bool comp_straight_entry(BlockCtx& ctx, MotionKind kind, const Pos9& target, P2 c, P2 p) {
  CutterComp& cc = ctx.s.comp;
  ModalState& s = ctx.s;
  const PlaneAxes ax = plane_axes(s.plane);
  const double r = cc.radius_mm;
  const double d = dist(c, p);
  if (d <= r) return tool_too_large(ctx, "the cutter compensation entry move", d);
  const double alpha = angle(c, p) + cc.side * kPi / 2;
  const P2 e = polar(p, r, alpha);
  cc.emitted_mm = motion_start(ctx);
  cc.detached = false;
  set_endpoint(cc, c);
  const Pos9 end = with_plane(target, ax, e);
  Pos9 prog_from = s.position_mm;
  double feed;
  if (!block_feed(ctx, (target - prog_from).norm(), feed)) return false;
  if (!enqueue(ctx, straight_item(ctx, kind, end, feed, std::cos(alpha), std::sin(alpha))))
    return false;
  cc.first_move = false;
  s.position_mm = end;
  cc.prog_a = p.a;
  cc.prog_b = p.b;
  return true;
}

// A concave corner from a line (the tool at `c`) to a line: back the previous line off along
// itself. `beta` is the turn at the corner, `theta` + `gamma` the previous line's direction.
bool end_line_before_line(BlockCtx& ctx, P2 c, double beta, double theta, double gamma) {
  const double half = (beta + kPi) / 2.0;
  if (half == 0.0)
    return ctx.fail(ErrorCode::CompGouge, block_loc(ctx),
                    "a zero degree inside corner cannot be compensated");
  const double retreat = ctx.s.comp.radius_mm / std::tan(half);
  return move_end_and_flush(ctx, polar(c, retreat, theta + gamma));
}

// A concave corner from an arc to the line from `o` to `p`: end the previous arc where the tool
// touches the new line.
bool end_arc_before_line(BlockCtx& ctx, P2 o, P2 p) {
  const CutterComp& cc = ctx.s.comp;
  const PlaneAxes ax = plane_axes(ctx.s.plane);
  const double r = cc.radius_mm;
  const Motion& pm = cc.queue.front().mo;
  const P2 pc = in_plane(cc.queue.front().center_mm, ax);
  const double oldrad = dist(pc, in_plane(cc.queue.front().end_mm, ax));
  const int pturn = turn_of(pm);
  const double base = angle(o, p);
  const double th = pturn > 0 ? base + kPi / 2 : base - kPi / 2;
  const double phi = angle(o, pc);
  const bool in = inside(cc.side, pturn);
  const double uncomp = in ? oldrad + r : oldrad - r;
  const double d = uncomp * std::cos(th - phi);
  const double l = (in ? d - r : d + r) / oldrad;
  if (l > 1.0 || l < -1.0) return gouge(ctx, "arc to straight motion");
  const double acl = std::acos(l);
  const double from_centre = (in == (pturn > 0) ? -acl : acl) + th + kPi;
  return move_end_and_flush(ctx, polar(pc, oldrad, from_centre));
}

}  // namespace

bool comp_straight(BlockCtx& ctx, MotionKind kind, const Pos9& target) {
  CutterComp& cc = ctx.s.comp;
  ModalState& s = ctx.s;
  if (ctx.w.has_code('G', 530))
    return ctx.fail(ErrorCode::G53Misused, ctx.loc_of(Group::NonModal),
                    "G53 with cutter radius compensation on");
  const PlaneAxes ax = plane_axes(s.plane);
  const double r = cc.radius_mm;
  const P2 c = in_plane(s.position_mm, ax), p = in_plane(target, ax);
  if (cc.first_move) return comp_straight_entry(ctx, kind, target, c, p);

  const P2 o{cc.prog_a, cc.prog_b};
  double feed;
  if (!block_feed(ctx, (target - comp_program_point(ctx)).norm(), feed)) return false;
  if (p == o) {  // no motion in the plane: the tool keeps its offset point
    const Pos9 end = with_plane(target, ax, c);
    if (!enqueue(ctx, straight_item(ctx, kind, end, feed, 0.0, 0.0))) return false;
    s.position_mm = end;
    return true;
  }
  double theta = angle(o, c);  // from the programmed point to the tool: the previous normal
  double alpha = angle(o, p);  // the new direction
  double beta = 0.0;           // the turn at the corner, pi/2 = straight on
  if (cc.side > 0) {
    if (theta < alpha) theta += 2 * kPi;
    beta = theta - alpha - kPi / 2;
  } else {
    if (alpha < theta) alpha += 2 * kPi;
    beta = alpha - theta - kPi / 2;
  }
  const double gamma = cc.side * kPi / 2;
  const P2 e = polar(p, r, alpha + gamma);
  const P2 mid = polar(o, r, alpha + gamma);
  bool concave = beta < -kCornerTolRad || beta > kPi + kCornerTolRad;
  if (!concave && beta > kPi - kCornerTolRad && front_is_arc(cc) &&
      !inside(cc.side, turn_of(cc.queue.front().mo)))
    concave = true;  // leaving an arc the tool was outside of, nearly reversing ("h" shape)

  if (!concave && beta > kCornerTolRad) {  // convex corner: an arc around it
    if (!move_end_and_flush(ctx, c)) return false;
    if (!corner_move(ctx, kind, o, mid, target, feed)) return false;
  } else if (concave) {
    if (!(front_is_arc(cc) ? end_arc_before_line(ctx, o, p)
                           : end_line_before_line(ctx, c, beta, theta, gamma)))
      return false;
  } else {  // straight on, or tangent
    dequeue(ctx);
    set_endpoint(cc, c);
  }
  const Pos9 end = with_plane(target, ax, e);
  if (!enqueue(ctx, straight_item(ctx, kind, end, feed, p.a - o.a, p.b - o.b))) return false;
  s.position_mm = end;
  cc.prog_a = p.a;
  cc.prog_b = p.b;
  return true;
}

namespace {

// The programmed arc's centre: `given` (G70's profile arcs), else from the block's words.
bool programmed_centre(BlockCtx& ctx, const Code& code, const Pos9& from, const Pos9& target,
                       const Pos9* given, Pos9& centre9) {
  if (given != nullptr) {
    centre9 = *given;
    return true;
  }
  return arc_centre(ctx, code, from, target, centre9);
}

// The feed of the compensated moves of an arc block: block_feed of the programmed arc.
bool arc_block_feed(BlockCtx& ctx, const Pos9& from, const Pos9& target, const Pos9& centre9,
                    bool ccw, int turns, double& feed) {
  Motion prog = motion_template(ctx, MotionKind::Arc);
  prog.start_mm = to_machine(from, ctx.machine.layout);
  prog.end_mm = to_machine(target, ctx.machine.layout);
  prog.center_mm = to_machine(centre9, ctx.machine.layout);
  prog.ccw = ccw;
  prog.turns = turns;
  return block_feed(ctx, motion_length_mm(prog), feed);
}

// What both arc moves under compensation start from: the plane, the tool radius, the signed
// direction and turns, whether the tool is inside the arc, and the arc's start and end in the
// plane.
struct ArcFrame {
  PlaneAxes ax;
  double r;
  bool ccw;  ///< G3
  int turn;
  bool tool_inside;
  P2 c, e;
};

ArcFrame arc_frame(const BlockCtx& ctx, const Code& code, const Pos9& target, int turns) {
  const CutterComp& cc = ctx.s.comp;
  const PlaneAxes ax = plane_axes(ctx.s.plane);
  const bool ccw = code.number10 == 30;
  const int turn = ccw ? turns : -turns;
  return ArcFrame{ax,
                  cc.radius_mm,
                  ccw,
                  turn,
                  inside(cc.side, turn),
                  in_plane(ctx.s.position_mm, ax),
                  in_plane(target, ax)};
}

// The entry arc: through the programmed end, tangent to the tool.
bool comp_arc_entry(BlockCtx& ctx, const Code& code, const Pos9& target, int turns,
                    const Pos9* centre_mm) {
  CutterComp& cc = ctx.s.comp;
  ModalState& s = ctx.s;
  const auto [ax, r, ccw, turn, tool_inside, c, e] = arc_frame(ctx, code, target, turns);
  const double d = dist(c, e);
  if (d <= r) return tool_too_large(ctx, "the radius of the cutter compensation entry arc", d);
  if (ctx.w.has('R') && tool_inside && std::fabs(ctx.w['R']->value) * ctx.scale() <= r)
    return tool_too_large(ctx, "the arc radius", std::fabs(ctx.w['R']->value) * ctx.scale());
  Pos9 centre9;
  if (!programmed_centre(ctx, code, s.position_mm, target, centre_mm, centre9)) return false;
  const P2 centre = in_plane(centre9, ax);
  if (!ctx.w.has('R') && tool_inside && dist(centre, c) <= r)
    return tool_too_large(ctx, "the arc radius", dist(centre, c));
  double feed;
  if (!arc_block_feed(ctx, s.position_mm, target, centre9, ccw, turns, feed)) return false;
  const double gamma = tool_inside ? angle(e, centre) : angle(centre, e);
  cc.first_move = false;
  cc.prog_a = e.a;
  cc.prog_b = e.b;
  const P2 ee = polar(e, r, gamma);
  // The compensated arc runs from the tool through `ee`; its centre lies on the line from
  // `ee` through the programmed centre, equidistant from both ends.
  const double half_chord = dist(c, ee) / 2.0;
  const double ab = angle(ee, centre);
  const double a_ang = angle(ee, c) - ab;
  if (std::fabs(std::cos(a_ang)) < kEqualTol)
    return tool_too_large(ctx, "the arc radius", dist(centre, e));
  const P2 nc = polar(ee, half_chord / std::cos(a_ang), ab);
  cc.emitted_mm = motion_start(ctx);
  cc.detached = false;
  if (cc.orientation != 0 && cc.orientation != 9) {  // lathe tool: move its origin first
    if (!enqueue(ctx, straight_item(ctx, MotionKind::Line, s.position_mm, s.feed_mm_min, 0, 0)))
      return false;
    set_endpoint(cc, c);
  }
  const Pos9 end = with_plane(target, ax, ee);
  if (!enqueue(ctx,
               arc_item(ctx, end, with_plane(end, ax, nc), turn, feed, sweep(c, nc, turn, ee))))
    return false;
  s.position_mm = end;
  return true;
}

// An arc after the entry move, at its corner with the previous move: the programmed centre and
// radius, its sense, the tool's side of it, the previous move's direction `theta` and the turn
// `beta` between the two.
struct CompArc {
  P2 centre;
  double radius;
  int turn;
  bool tool_inside;
  double theta, beta;
};

// A concave corner from a line to the arc: where the tool touches the arc (the line ends there).
bool line_to_arc_meet(BlockCtx& ctx, const CompArc& arc, P2& mid) {
  const double r = ctx.s.comp.radius_mm;
  const double cy = arc.radius * std::sin(arc.beta - kPi / 2);
  const double from_centre = arc.tool_inside ? arc.radius - r : arc.radius + r;
  const double toward = arc.tool_inside ? cy + r : cy - r;
  const double l = toward / from_centre;
  if (l > 1.0 || l < -1.0)
    return ctx.fail(ErrorCode::CompGouge, block_loc(ctx),
                    "arc move in concave corner cannot be reached by the tool without "
                    "gouging");
  const double as = std::asin(l);
  const double theta = arc.theta;
  const double ang = arc.tool_inside ? (arc.turn > 0 ? theta + as : theta - as)
                                     : (arc.turn > 0 ? theta + kPi - as : theta + kPi + as);
  mid = polar(arc.centre, from_centre, ang);
  return true;
}

// A concave corner from an arc to the arc: where the two offset circles meet.
bool arc_to_arc_meet(BlockCtx& ctx, const CompArc& arc, P2& mid) {
  const CutterComp& cc = ctx.s.comp;
  const PlaneAxes ax = plane_axes(ctx.s.plane);
  const double r = cc.radius_mm;
  const CompQueued& prev = cc.queue.front();
  const P2 pc = in_plane(prev.center_mm, ax);
  const double oldrad = dist(pc, in_plane(prev.end_mm, ax));
  const double newrad = arc.tool_inside ? arc.radius - r : arc.radius + r;
  const double cc_dist = dist(pc, arc.centre);
  if (oldrad == 0.0 || cc_dist == 0.0)
    return ctx.fail(ErrorCode::CompGouge, block_loc(ctx),
                    "arc to arc motion with both arcs about the same centre cannot be "
                    "compensated");
  const double a = (oldrad * oldrad + cc_dist * cc_dist - newrad * newrad) / (2 * oldrad * cc_dist);
  if (a > 1.0 || a < -1.0) return gouge(ctx, "arc to arc motion");
  const double pull = std::acos(a);
  const double cc_dir = angle(pc, arc.centre);
  const bool prev_inside = inside(cc.side, turn_of(prev.mo));
  const double dir = (prev_inside == (arc.turn > 0)) ? cc_dir + pull : cc_dir - pull;
  mid = polar(pc, oldrad, dir);
  return true;
}

}  // namespace

bool comp_arc(BlockCtx& ctx, const Code& code, const Pos9& target, int turns,
              const Pos9* centre_mm) {
  CutterComp& cc = ctx.s.comp;
  ModalState& s = ctx.s;
  if (cc.first_move) return comp_arc_entry(ctx, code, target, turns, centre_mm);
  const auto [ax, r, ccw, turn, tool_inside, c, e] = arc_frame(ctx, code, target, turns);

  const P2 o{cc.prog_a, cc.prog_b};
  const Pos9 o9 = comp_program_point(ctx);
  Pos9 centre9;
  if (!programmed_centre(ctx, code, o9, target, centre_mm, centre9)) return false;
  const P2 centre = in_plane(centre9, ax);
  double feed;
  if (!arc_block_feed(ctx, o9, target, centre9, ccw, turns, feed)) return false;

  const double arc_radius = dist(centre, e);
  const double theta = angle(o, c) - cc.side * kPi / 2;  // direction of the previous move
  double delta = angle(o, centre);
  const double alpha = ccw ? delta - kPi / 2 : delta + kPi / 2;  // the arc's start direction
  double beta = cc.side > 0 ? theta - alpha : alpha - theta;
  if (beta > 1.5 * kPi)
    beta -= 2 * kPi;
  else if (beta < -kPi / 2)
    beta += 2 * kPi;
  double gamma = 0.0;
  if (tool_inside) {
    gamma = angle(e, centre);
    if (arc_radius <= r) return tool_too_large(ctx, "the arc radius", arc_radius);
  } else {
    gamma = angle(centre, e);
    delta += kPi;
  }
  const P2 ne = polar(e, r, gamma);
  const Pos9 end = with_plane(target, ax, ne);
  const double main_sweep = sweep(o, centre, turn, e);

  const bool concave = beta < -kCornerTolRad || beta > kPi + kCornerTolRad ||
                       (std::fabs(beta - kPi) < kCornerTolRad && !tool_inside);
  if (concave) {
    const CompArc arc{centre, arc_radius, turn, tool_inside, theta, beta};
    P2 mid;
    if (!(front_is_arc(cc) ? arc_to_arc_meet(ctx, arc, mid) : line_to_arc_meet(ctx, arc, mid)))
      return false;
    if (!move_end_and_flush(ctx, mid)) return false;
  } else if (beta > kCornerTolRad) {  // convex corner: an arc around it first
    dequeue(ctx);
    if (!corner_move(ctx, MotionKind::Arc, o, polar(o, r, delta), target, feed)) return false;
  } else {  // tangent
    dequeue(ctx);
    set_endpoint(cc, c);
  }
  if (!enqueue(ctx, arc_item(ctx, end, with_plane(end, ax, centre), turn, feed, main_sweep)))
    return false;
  cc.prog_a = e.a;
  cc.prog_b = e.b;
  s.position_mm = end;
  return true;
}

}  // namespace gm
