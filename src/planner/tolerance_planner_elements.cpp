// TolerancePlanner's elements: corners, arcs and chains, runs of small turns; their shares.
#include "planner/tolerance_planner.hpp"

#include "common/units.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>

namespace gm {

namespace {

double min_positive(double a, double b) {
  if (a > 0.0 && b > 0.0) return std::min(a, b);
  return a > 0.0 ? a : b;
}

}  // namespace

void TolerancePlanner::add_corner(const Block& prev, const Block& b) {
  double tol = min_positive(prev.m.path_tolerance_mm, b.m.path_tolerance_mm);
  // A tangent G61 join rounds by no more than the BLU rounding does: planned within it.
  if (prev.tangent_exit) tol = min_positive(tol, exact_path_tolerance());
  if (prev.stop_after) return;
  if (!(tol > 0.0)) {
    // Without a tolerance the turn matters only to a run of small turns being gathered (a turn
    // ends it: the run's bound does not cover it), and to a block with a tolerance that may
    // start within τ (plan_untoleranced computes it then).
    if ((run_.open || run_.vertices > 0) && join_turn(prev, b) > kMinTurn) end_run();
    untoleranced_.push_back(Untoleranced{prev.seq, false, prev.t1, prev.t1 + filter_.tau_s()});
    return;
  }
  const double turn = join_turn(prev, b);
  if (!(turn > kMinTurn)) return;
  Element e = corner_element(prev, b, turn, tol);
  // A dwell that drains the filter is a full stop whatever the corner's decision: the elements
  // decided before it are parted from what lies past it (tolerance_near, part_zone).
  if (e.pause0 > 0.0 && !(corner_moment(e.pause0) > 0.0)) e.stopped = true;
  const double seg = prev.s1 - prev.s0;
  const bool dense = dense_runs_ && seg < kDenseRunSegment * e.v100 * filter_.tau_s();
  const double run_turn = dense ? kDenseRunTurn : kRunTurn;
  const double delta_share = dense ? kDenseRunDeltaShare : kRunDeltaShare;
  if (prev.m.kind == MotionKind::Line && b.m.kind == MotionKind::Line && turn <= run_turn &&
      turn * e.v100 * filter_.abs_moment_s() <= delta_share * tol &&
      seg < prev.vmax * filter_.tau_s()) {
    add_run_vertex(e, seg);
  } else {
    end_run();
    push_element(e);
  }
}

TolerancePlanner::Element TolerancePlanner::corner_element(const Block& prev, const Block& b,
                                                           double turn, double tol) {
  Element e;
  e.kind = ElementKind::Corner;
  e.seq = prev.seq;
  e.t0 = prev.t1;
  e.t1 = b.t0;
  e.s0 = e.s1 = prev.s1;
  e.tol_mm = tol;
  e.turn = turn;
  e.pause0 = prev.dwell_after_s;
  e.vmax = std::max(prev.vmax, b.vmax);
  e.v100 = std::max(prev.v100, b.v100);
  return e;
}

TolerancePlanner::Element TolerancePlanner::arc_element(const Block& b) {
  const double r = std::min(b.g.r0_mm, b.g.r1_mm);
  Element e;
  e.kind = ElementKind::Arc;
  e.seq = e.seq_last = b.seq;
  e.t0 = b.t0;
  e.t1 = b.t1;
  e.s0 = b.s0;
  e.s1 = b.s1;
  e.tol_mm = b.m.path_tolerance_mm;
  e.kappa = r > 0.0 ? 1.0 / r : kInf;
  e.vmax = b.vmax;
  e.v100 = b.v100;
  // A circle (the start and end radii within 0.1 µm) may be pre-compensated, and so may a near
  // circle, whose radii differ by at most 1 % (CAM output rounded to 3 or 4 decimals), planned
  // as the circle of its larger radius plus its extra term (ArcPrecompCheck::spiral_mm); not a
  // spiral beyond that.
  const double dr = std::abs(b.g.r0_mm - b.g.r1_mm);
  if (r > 0.0 && !b.g.rest_moves && (dr <= 1e-4 || dr <= kNearCircle * r)) {
    e.radius = dr <= 1e-4 ? r : r + dr;
    e.spiral = dr <= 1e-4 ? 0.0 : dr;
    e.sweep = std::abs(b.g.sweep_rad);
  }
  return e;
}

double TolerancePlanner::join_turn(const Block& prev, const Block& b) {
  return (b.g.tangent_at_fraction(0.0) - prev.g.tangent_at_fraction(1.0)).norm();
}

bool TolerancePlanner::same_circle(const Block& first, const Block& prev, const Block& b) const {
  // Nothing between prev and b (no stop, dwell or event after prev; tangent: no corner),
  // circles (not near circles) that turn once, with the same feed, tolerance and mode; the
  // circle and lead those of `first` (the chain's first block: no drift along a chain).
  if (!precomp_ || prev.m.kind != MotionKind::Arc || b.m.kind != MotionKind::Arc ||
      prev.stop_after || !prev.after.empty() || !splits(prev.m) || !splits(b.m))
    return false;
  if (prev.m.path_mode != PathMode::Continuous || b.m.path_mode != PathMode::Continuous ||
      !(b.m.path_tolerance_mm > 0.0) || prev.m.path_tolerance_mm != b.m.path_tolerance_mm ||
      prev.v100 != b.v100)
    return false;
  // The circle and lead those of the chain's first block; tangent as add_corner judges it (no
  // corner element between them).
  return one_circle(first.g, b.g) && !(join_turn(prev, b) > kMinTurn);
}

bool TolerancePlanner::one_curve(const BlockGeometry& g, const BlockGeometry& h) {
  if (h.ax.a != g.ax.a || h.ax.b != g.ax.b || (h.sweep_rad > 0.0) != (g.sweep_rad > 0.0))
    return false;
  if (one_circle(g, h)) return true;
  const double lo = std::min({g.r0_mm, g.r1_mm, h.r0_mm, h.r1_mm}),
               hi = std::max({g.r0_mm, g.r1_mm, h.r0_mm, h.r1_mm});
  return lo > 0.0 && hi <= kG61CurveRatio * lo;
}

bool TolerancePlanner::one_circle(const BlockGeometry& g, const BlockGeometry& h) {
  if (h.ax.a != g.ax.a || h.ax.b != g.ax.b || g.rest_moves || h.rest_moves ||
      (h.sweep_rad > 0.0) != (g.sweep_rad > 0.0))
    return false;
  // The same circle, as arc_element's circles: centres and radii within 0.1 µm.
  constexpr double kSame = 1e-4;
  if (std::abs(h.center_mm[h.ax.a] - g.center_mm[g.ax.a]) > kSame ||
      std::abs(h.center_mm[h.ax.b] - g.center_mm[g.ax.b]) > kSame ||
      std::abs(g.r0_mm - g.r1_mm) > kSame || std::abs(h.r0_mm - h.r1_mm) > kSame ||
      std::abs(h.r0_mm - g.r0_mm) > kSame)
    return false;
  // The same lead per radian along the normal: a helix goes on as the same helix.
  const int n = g.ax.n;
  const double lead_g = (g.end_mm[n] - g.start_mm[n]) / g.sweep_rad,
               lead_h = (h.end_mm[n] - h.start_mm[n]) / h.sweep_rad;
  return std::abs(lead_g - lead_h) <= 1e-9 * std::max(1.0, std::abs(lead_g));
}

TolerancePlanner::Element* TolerancePlanner::growing_arc(const Block& prev) {
  if (elems_.empty()) return nullptr;
  Element& e = elems_.back();
  return e.kind == ElementKind::Arc && !e.decided && e.seq_last == prev.seq ? &e : nullptr;
}

const TolerancePlanner::Element* TolerancePlanner::arc_of(const Block& b) const {
  if (b.m.kind != MotionKind::Arc) return nullptr;
  for (const Element& e : elems_)
    if (e.kind == ElementKind::Arc && e.seq <= b.seq && b.seq <= e.seq_last) return &e;
  return nullptr;
}

const TolerancePlanner::Element* TolerancePlanner::chain_of(const Block& b) const {
  const Element* e = arc_of(b);
  return e != nullptr && e->seq_last > e->seq ? e : nullptr;
}

double TolerancePlanner::share_of(double tol) const {
  return std::max(tol, 2.0 * cfg_.rounding_mm) - cfg_.rounding_mm;  // below the BLU: no hold
}

double TolerancePlanner::reserve_of(double tol) const {
  if (!(cfg_.speed_error_s > 0.0)) return 0.0;
  // share − reserve grows with tol, so the smaller tolerance a decision takes stays safe.
  const double v_rapid = units::mm_min_to_mm_s(cfg_.rapid_mm_min) * cfg_.max_override;
  return std::min(0.5 * share_of(tol), v_rapid * cfg_.speed_error_s);
}

MismatchReserve TolerancePlanner::mismatch_reserve(const Element& e, double tol) const {
  MismatchReserve r;
  r.max_mm = reserve_of(tol);
  if (!(cfg_.speed_error_s > 0.0)) return r;  // no mismatch: every reserve 0
  r.m_s = cfg_.speed_error_s;
  r.v_reach_mm_s = kInf;
  // e's error is active at samples from its start (a corner's vertex) until τ after its end;
  // their chain windows reach τ further back. The blocks with motion in those windows are those
  // less than τ of travel before e's start or after its end: travel time counts each block's
  // fastest time and the dwells between them but no stop (the interpolator holds at a stop only
  // until the Acc/Dec filter drains, which can be shorter than the chain), so it is never longer
  // than the actual time. Every such block must be in the window (else: the largest reserve).
  const double tau = filter_.tau_s();
  const std::size_t n = window_.size();
  // Blocks ending after e's start and starting before its end: e's own.
  const std::size_t first =
      static_cast<std::size_t>(std::partition_point(window_.begin(), window_.end(),
                                                    [&](const Block& b) { return b.t1 <= e.t0; }) -
                               window_.begin());
  double v = 0.0;
  auto speed = [](const Block& b) { return std::min(b.vmax, b.cap_all); };
  std::size_t k = first;
  for (; k < n && window_[k].t0 < e.t1; ++k) v = std::max(v, speed(window_[k]));
  // After e: travel time from e's end to each block's start (a stop between counted as 0).
  for (double gap = 0.0; k < n; ++k) {
    const Block& b = window_[k];
    const Block* p = k > 0 ? &window_[k - 1] : nullptr;
    if (p != nullptr && p->t1 >= e.t1)
      gap += p->dwell_after_s;
    else
      gap = std::max(0.0, b.t0 - e.t1 - (p == nullptr || p->stop_after ? tau : 0.0));
    if (!(gap < tau)) break;
    v = std::max(v, speed(b));
    gap += b.t1 - b.t0;
    if (!(gap < tau)) break;
  }
  // Ran off the window's end: blocks not yet read may be within reach.
  if (k == n && !ended_) return r;
  // Before e: travel time from each block's end to e's start.
  double gap = 0.0;
  for (k = first; k-- > 0;) {
    const Block& b = window_[k];
    gap = k + 1 < first ? gap + window_[k + 1].t1 - window_[k + 1].t0 + b.dwell_after_s
                        : std::max(0.0, e.t0 - b.t1 - (b.stop_after ? tau : 0.0));
    if (!(gap < tau)) break;
    v = std::max(v, speed(b));
  }
  if (k == static_cast<std::size_t>(-1) && emitted_t1_ > -kInf) {
    // The window's front is within reach: so may be the block handed on before it (the gap
    // between them, a dwell and perhaps a stop, counted at least gap − τ).
    const Block& f = window_.front();
    const double to_front = first > 0 ? gap + (f.t1 - f.t0) : std::max(0.0, e.t0 - f.t0);
    if (to_front + std::max(0.0, f.t0 - emitted_t1_ - tau) < tau) return r;
  }
  r.v_reach_mm_s = v;
  return r;
}

void TolerancePlanner::add_run_vertex(const Element& corner, double seg_before_mm) {
  if (run_.open && corner.t0 > run_.chunk.t0 + filter_.tau_s()) close_run_chunk();
  if (run_.vertices == 0) run_.id = ++runs_;
  Element& c = run_.chunk;
  if (!run_.open) {
    run_.open = true;
    c = corner;
    c.kind = ElementKind::Run;
    c.run_id = run_.id;
    c.kappa = c.delta = c.turn = c.pause0 = 0.0;
  }
  c.t1 = corner.t1;
  c.s1 = corner.s1;
  c.tol_mm = std::min(c.tol_mm, corner.tol_mm);
  c.vmax = std::max(c.vmax, corner.vmax);
  c.v100 = std::max(c.v100, corner.v100);
  c.delta = std::max(c.delta, corner.turn);
  // The run's first vertex is charged to δ alone (the line before it may be long); every later
  // one to the line before it, which lies inside any stretch of path that holds both ends.
  if (run_.vertices > 0) c.kappa = std::max(c.kappa, corner.turn / seg_before_mm);
  if (run_.vertices < kMinRunVertices) run_.corners.push_back(corner);
  ++run_.vertices;
}

void TolerancePlanner::close_run_chunk() {
  if (!run_.open) return;
  run_.open = false;
  if (run_.vertices < kMinRunVertices) {
    for (const Element& c : run_.corners) push_element(c);
  } else {
    push_element(run_.chunk);
  }
  run_.corners.clear();
}

void TolerancePlanner::end_run() {
  close_run_chunk();
  run_.vertices = 0;
}

void TolerancePlanner::push_element(Element e) {
  // Weights: what the element costs at a speed, in a corner's units (V·D(0)·|Δu| for a corner):
  // a run's (κ·V·σ²/2 + δ·M₁)/D(0) at 100 % feed, so that the corners beside it keep a fair share.
  if (e.kind == ElementKind::Run)
    e.weight = std::max(kMinTurn, (0.5 * e.kappa * e.v100 * filter_.variance_s2() +
                                   e.delta * filter_.abs_moment_s()) /
                                      corner_moment(0.0));
  else
    e.weight = e.kind == ElementKind::Arc ? 1.0 : e.turn;
  e.cum = weight_total_;
  weight_total_ += e.weight;
  e.claim_state = Element::Claim::Unassigned;
  e.claim = 0.0;
  if (e.kind == ElementKind::Corner && e.turn <= kClaimTurn) ++claim_candidates_;
  elems_.push_back(e);
}

}  // namespace gm
