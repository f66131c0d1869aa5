// TolerancePlanner: look-ahead window, per-element budgets, speed caps by zone, corner pauses.
#include "planner/tolerance_planner.hpp"

#include "common/units.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iterator>
#include <limits>

namespace gm {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// The next float up and down (finite x): a step of the bit pattern, as std::nextafter.
double float_up(double x) {
  if (x == 0.0) return std::numeric_limits<double>::denorm_min();
  const auto b = std::bit_cast<std::int64_t>(x);
  return std::bit_cast<double>(x > 0.0 ? b + 1 : b - 1);
}
double float_down(double x) {
  return -float_up(-x);
}

/// The smallest float v >= 0 with f(v) true, f monotone (false then true), from a guess a few
/// floats off: NaN when it is not within `reach` steps of the guess.
template <class F>
double first_true_near(double guess, F f, int reach = 8) {
  double v = guess;
  for (int k = 0; k < reach && v > 0.0 && f(float_down(v)); ++k) v = float_down(v);
  for (int k = 0; k < reach && !f(v); ++k) v = float_up(v);
  if (!f(v) || (v > 0.0 && f(float_down(v)))) return std::nan("");
  return v;
}

/// The smallest speed v at which an element enters the zone [s0 − v·t, s1 + v·t] by the zone
/// tests (zone_range, narrowed_speed_in_zones' `joins`): before it (its end b_s1) once
/// !(b_s1 <= (s0 − v·t) − 1e-9), after it (its start a_s0) once a_s0 < (s1 + v·t) + 1e-9, each
/// operation rounded. Solved one rounding at a time, from the outside in: the zone end z that
/// the 1e-9 test turns at, then the product u = v·t that the sum with s0 or s1 turns at
/// (between two neighbouring sums: their midpoint less s, up to one rounding), then v. NaN
/// when a step does not land within a few floats (the caller halves then).
double first_joining_speed(double s0, double s1, double t, const double* b_s1, const double* a_s0) {
  const double nan = std::nan("");
  if (!(t > 0.0)) return nan;
  auto speed_for = [t](double u) {  // the smallest v with v·t >= u
    if (!(u >= 0.0)) return 0.0;
    return first_true_near(u / t, [&](double v) { return v * t >= u; });
  };
  double v = kInf;
  if (a_s0 != nullptr) {
    const double a = *a_s0;
    const double z = first_true_near(a - 1e-9, [&](double y) { return a < y + 1e-9; });
    const double mid = 0.5 * ((float_down(z) - s1) + (z - s1));
    const double u = first_true_near(std::max(0.0, mid), [&](double w) { return s1 + w >= z; });
    v = std::min(v, speed_for(u));
  }
  if (b_s1 != nullptr) {
    const double b = *b_s1;
    // The largest zone start y with !(b <= y − 1e-9): the smallest with b <= y − 1e-9, less one.
    const double y_out = first_true_near(b + 1e-9, [&](double y) { return b <= y - 1e-9; });
    const double z = float_down(y_out);
    const double mid = 0.5 * ((s0 - z) + (s0 - y_out));
    const double u = first_true_near(std::max(0.0, mid), [&](double w) { return s0 - w <= z; });
    v = std::min(v, speed_for(u));
  }
  return v;
}

constexpr double kMinTurn = 1e-9;
/// A vertex between two G1 lines joins a run of small turns when it turns by at most this
/// (|Δu|, about 5.7°), by so little that the run's δ term alone keeps within the tolerance at
/// 100 % feed (δ·V·M₁ <= tol; larger turns do better corner by corner, where they can pause),
/// and the line before it is shorter than τ of travel. A run of fewer than kMinRunVertices
/// vertices is planned corner by corner.
constexpr double kRunTurn = 0.1;
/// A corner turning by at most this (|Δu|, about 0.57°: CAM output rounded to 3 decimals turns
/// 0 to 0.13° at joins meant to be tangent) may claim its error at its fastest speed, above
/// 100 % feed too (assign_claims).
constexpr double kClaimFreeTurn = 0.01;
/// A corner turning by at most this (|Δu|, about 5.7°: arcs rounded to 4 decimals of an inch
/// meet at kinks of 0.1 to 2°) may claim its error at 100 % feed, its zone capped there.
constexpr double kClaimTurn = 0.1;
/// A near circle: its radii differ by at most this fraction of the smaller;
/// ArcPrecompCheck::spiral_mm's bound assumes Δr/r small.
constexpr double kNearCircle = 0.01;
/// A block after a pre-compensated arc whose fastest speed is below this fraction of the arc's
/// v_p makes the arc's end a stop for its end rows (emit_front): measured, 2 of 450 random
/// feed-changing chains were over P (to 107 %) with the moving rows there, 0 with these.
constexpr double kCrawlRatio = 0.1;
/// A pre-compensated arc is cut at zone boundaries no nearer its ends than this many samples of
/// travel at v_p: its end rows (ArcEndRows::kSpan advances), the radial blend (two samples)
/// and the speed hold before its end lie within them.
constexpr double kCompEndSamples = ArcEndRows::kSpan + 2;
/// A chain's ends are planned slower than its middle (slower_ends) only where its middle gains
/// more than this fraction of its speed.
constexpr double kSlowerEndsGain = 0.02;
constexpr int kMinRunVertices = 3;
constexpr double kRunDeltaShare = 4.0;

double min_positive(double a, double b) {
  if (a > 0.0 && b > 0.0) return std::min(a, b);
  return a > 0.0 ? a : b;
}

}  // namespace

TolerancePlanner::TolerancePlanner(const FilterMoments& filter, const PlannerConfig& cfg,
                                   CanonSource& upstream)
    : filter_(filter), cfg_(cfg), merger_(upstream) {
  if (cfg_.precompensate_arcs && filter_.overshoot_s() == 0.0 && filter_.undershoot_s() == 0.0) {
    precomp_.emplace(filter_.weights(), filter_.period_s());
    if (!precomp_->enabled())
      precomp_.reset();
    else
      residual_.emplace(*precomp_);
  }
}

CornerMomentGrid& TolerancePlanner::grid_d() {
  // Built at the first corner: a program without a tolerance never pays for it.
  if (!grid_d_) grid_d_.emplace(filter_);
  return *grid_d_;
}

double TolerancePlanner::corner_moment(double pause_s) const {
  // Most corners ask for the same pause (none): D is a bisection over the window each time.
  if (!(pause_s == moment_pause_s_)) {
    moment_pause_s_ = pause_s;
    moment_s_ = filter_.corner_moment_s(pause_s);
  }
  return moment_s_;
}

void TolerancePlanner::pull() {
  if (!merger_.next(scratch_)) {
    ended_ = true;
    untoleranced_.clear();  // no block with a tolerance follows them
    end_exact_path(nullptr, nullptr);
    return;
  }
  const Motion* m = std::get_if<Motion>(&scratch_);
  if (m != nullptr) pulled_g_ = BlockGeometry::of(*m);
  if (m == nullptr || !(pulled_g_.length_mm > 0.0)) {  // not a block of the path
    end_exact_path(nullptr, nullptr);
    hold_after_last();
    return;
  }
  end_exact_path(m, &pulled_g_);
  Block& b = push_block(*m);
  const bool toleranced = b.m.path_tolerance_mm > 0.0;
  if (toleranced && !untoleranced_.empty()) plan_untoleranced(b);
  const Block* prev = window_.size() >= 2 ? &window_[window_.size() - 2] : nullptr;
  // Arcs on one circle (split circles, helices written as half turns) are one arc element, a
  // chain (its ends may be planned slower than its middle: slower_ends).
  Element* growing = prev != nullptr ? growing_arc(*prev) : nullptr;
  const Block* first = prev;  // the circle's first block: the chain's, or prev
  if (growing != nullptr && growing->seq < prev->seq)
    first = &window_[window_.size() - 1 - static_cast<std::size_t>(b.seq - growing->seq)];
  const bool on_circle = prev != nullptr && same_circle(*first, *prev, b);
  if (prev != nullptr) add_corner(*prev, b);
  if (b.m.kind == MotionKind::Arc) end_run();
  // Afresh: a join that is not tangent to the rounding pushed a corner (and elements move).
  growing = on_circle ? growing_arc(*prev) : nullptr;
  if (growing != nullptr && growing->chainable) {  // the chain grows by b
    growing->seq_last = b.seq;
    growing->t1 = b.t1;
    growing->s1 = b.s1;
    growing->sweep += std::abs(b.g.sweep_rad);
  } else if (b.m.kind == MotionKind::Arc && toleranced) {
    Element e = arc_element(b);
    e.split = splits(b.m);
    e.chainable = e.radius > 0.0 && e.spiral == 0.0;  // a near circle's radius drifts
    push_element(e);
  } else if (b.m.kind == MotionKind::Arc) {
    untoleranced_.push_back(Untoleranced{b.seq, true, b.t0, b.t1 + filter_.tau_s()});
  }
  // Exact stop (G61.1, G9) stops here; exact path (G61) when the next item is known.
  if (b.m.path_mode == PathMode::ExactStop) mark_stop(b);
  if (!toleranced) drop_untoleranced(b.t1);
}

void TolerancePlanner::plan_untoleranced(const Block& b) {
  // What b starts before the end of is in b's samples: planned for b's tolerance
  // (tolerance_near then takes the smallest around it).
  const double tol = b.m.path_tolerance_mm;
  const std::uint64_t first = window_.front().seq;
  const std::size_t group_from = elems_.size();
  for (const Untoleranced& c : untoleranced_) {
    if (!(b.t0 < c.end) || c.seq < first) continue;
    const std::size_t i = static_cast<std::size_t>(c.seq - first);
    const Block& p = window_[i];
    Element e;
    if (c.arc) {
      e = arc_element(p);
      e.tol_mm = tol;
      e.split = splits(p.m);
    } else {
      const Block& n = window_[i + 1];
      const double turn = join_turn(p, n);
      if (!(turn > kMinTurn)) continue;
      e = corner_element(p, n, turn, tol);
    }
    e.untol_for = b.seq;
    push_element(e);
  }
  if (elems_.size() > group_from) {
    const double t1 = elems_[elems_.size() - 1].t1;
    for (std::size_t k = group_from; k < elems_.size(); ++k) elems_[k].group_t1 = t1;
  }
  untoleranced_.clear();
}

void TolerancePlanner::drop_untoleranced(double t_s) {
  // A block starting from t_s on no longer sees what ended before it.
  while (!untoleranced_.empty() && untoleranced_.front().end <= t_s) untoleranced_.pop_front();
}

void TolerancePlanner::end_exact_path(const Motion* next, const BlockGeometry* next_g) {
  if (window_.empty()) return;
  Block& last = window_.back();
  if (last.m.path_mode != PathMode::ExactPath || last.stop_after || last.tangent_exit) return;
  if (next != nullptr && last.after.empty() && exact_path_passes(last, *next, *next_g))
    last.tangent_exit = true;
  else
    mark_stop(last);
}

bool TolerancePlanner::exact_path_passes(const Block& prev, const Motion& next,
                                         const BlockGeometry& next_g) const {
  // LinuxCNC (src/emc/tp/tp.c, tpSetupTangent, and handleModeChange before it): no tangency
  // between a rapid and a feed move, with a rotary axis moving, or at a reversal within 2°.
  // Otherwise the velocity step v·(u2 − u1) at the join, taken within one period T, must
  // accelerate each axis by less than the kink ratio 0.1 of its acceleration limit a:
  // max_i |u2_i − u1_i|·(v/T + a)/a < 0.1, halved (BLEND_ACC_RATIO_TANGENTIAL 0.5) when an arc
  // takes part; v is the slower of the two blocks at the largest override. Here a is the
  // filter's mean acceleration to the rapid speed, V_rapid/τ (610 mm/s² on the default machine),
  // the same on every axis, and T the interpolation period.
  if ((prev.m.kind == MotionKind::Rapid) != (next.kind == MotionKind::Rapid)) return false;
  constexpr int kLinear = 3;
  const AxisVec d_prev = prev.m.end_mm - prev.m.start_mm, d_next = next.end_mm - next.start_mm;
  if (d_prev.tail<kMaxAxes - kLinear>().cwiseAbs().maxCoeff() > 0.0 ||
      d_next.tail<kMaxAxes - kLinear>().cwiseAbs().maxCoeff() > 0.0)
    return false;
  const AxisVec u1 = prev.g.tangent_at_fraction(1.0), u2 = next_g.tangent_at_fraction(0.0);
  constexpr double kSharpCornerRad = 2.0 * 3.14159265358979323846 / 180.0;
  if ((u1 + u2).squaredNorm() < kSharpCornerRad * kSharpCornerRad) return false;
  const double v_next = speed_at_100_mm_s(next, next_g.length_mm) * cfg_.max_override;
  // An arc keeps today's G61 (full feed, the filter's steady shrink κ·V²·σ²/2): one at least τ
  // of travel long reaches that shrink between stops as well, so passing its joins adds nothing
  // to its error; a shorter one (a fillet) passed at speed would be blended like a corner of its
  // whole turn, so its joins stop.
  const double tau = filter_.tau_s();
  if (prev.m.kind == MotionKind::Arc && prev.g.length_mm < prev.vmax * tau) return false;
  if (next.kind == MotionKind::Arc && next_g.length_mm < v_next * tau) return false;
  const double v = std::min(prev.vmax, v_next);
  const double a = units::mm_min_to_mm_s(cfg_.rapid_mm_min) / tau;
  const double a_inst = v / filter_.period_s() + a;
  double scale = (u2 - u1).cwiseAbs().maxCoeff() * a_inst / a;
  constexpr double kTangentialAccRatio = 0.5, kKinkRatio = 0.1;
  if (prev.m.kind == MotionKind::Arc || next.kind == MotionKind::Arc) scale /= kTangentialAccRatio;
  return scale < kKinkRatio;
}

void TolerancePlanner::hold_after_last() {
  if (window_.empty()) {
    make_ready(Canon(scratch_));
    return;
  }
  Block& last = window_.back();
  if (const auto* d = std::get_if<Dwell>(&scratch_)) last.dwell_after_s += d->seconds;
  if (const auto* e = std::get_if<Event>(&scratch_); e != nullptr && e->kind == EventKind::End)
    mark_stop(last);
  last.after.push_back(scratch_);
}

double TolerancePlanner::speed_at_100_mm_s(const Motion& m, double length_mm) const {
  double v100 = 0.0;
  if (m.kind == MotionKind::Rapid)
    v100 = units::mm_min_to_mm_s(cfg_.rapid_mm_min);
  else if (m.inverse_time_s > 0.0)
    v100 = length_mm / m.inverse_time_s;
  else
    v100 = units::mm_min_to_mm_s(m.feed_mm_min);
  return std::max(v100, 1e-9);
}

TolerancePlanner::Block& TolerancePlanner::push_block(const Motion& m) {
  const double tau = filter_.tau_s();
  // The block is built in its slot at the window's end (no Block copied); every field is set
  // here, since the slot holds an earlier block.
  Block& b = window_.push_back_slot();
  const Block* prev = window_.size() >= 2 ? &window_[window_.size() - 2] : nullptr;
  const BlockGeometry& g = pulled_g_;
  b.m = m;
  b.g = g;
  b.seq = ++seq_;
  b.after.clear();
  b.dwell_after_s = 0.0;
  b.stop_after = false;
  b.forced_stop = false;
  b.tangent_exit = false;
  const double L = g.length_mm;
  b.v100 = speed_at_100_mm_s(m, L);
  b.vmax = b.v100 * cfg_.max_override;
  b.s0 = s_end_;
  b.s1 = s_end_ + L;
  double gap_s = 0.0;
  if (prev != nullptr) gap_s = prev->dwell_after_s + (prev->stop_after ? tau : 0.0);
  b.t0 = t_end_ + gap_s;
  b.t1 = b.t0 + L / b.vmax;
  s_end_ = b.s1;
  t_end_ = b.t1;
  b.cap_all = kInf;
  if (m.path_tolerance_mm > 0.0 && (cfg_.speed_error_s > 0.0 || cfg_.drive_speed_mm_s < kInf)) {
    // The mismatch at a sample of b comes from the speeds within one chain length before it:
    // b and the blocks the chain still holds when b starts keep to reserve/speed_error; and so
    // does the drive command, kept below saturation by the drive's speed.
    const double v = std::min(
        cfg_.drive_speed_mm_s,
        cfg_.speed_error_s > 0.0 ? reserve_of(m.path_tolerance_mm) / cfg_.speed_error_s : kInf);
    b.cap_all = v;
    for (auto it = std::next(window_.rbegin());  // the blocks before b
         it != window_.rend() && it->t1 > b.t0 - tau; ++it)
      it->cap_all = std::min(it->cap_all, v);
  }
  return b;
}

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
  if (prev.m.kind == MotionKind::Line && b.m.kind == MotionKind::Line && turn <= kRunTurn &&
      turn * e.v100 * filter_.abs_moment_s() <= kRunDeltaShare * tol &&
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
  const BlockGeometry &g = first.g, &h = b.g;
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
  if (!(std::abs(lead_g - lead_h) <= 1e-9 * std::max(1.0, std::abs(lead_g)))) return false;
  // Tangent as add_corner judges it (no corner element between them).
  return !(join_turn(prev, b) > kMinTurn);
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

double TolerancePlanner::emit_horizon_t(const Block& b) const {
  const Element* chain = chain_of(b);
  return chain != nullptr ? std::max(b.t1, chain->t1) : b.t1;
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

void TolerancePlanner::mark_stop(Block& b) {
  if (b.stop_after) return;
  end_run();
  b.stop_after = true;
  // A chain whose step response overshoots (FIR + a type-2 servo, tolerance_on = encoder) runs
  // past the end of a block it stops at, along the block's end tangent, by up to V·∫(S − 1)⁺:
  // the stop is planned as a corner from u1 to rest (|Δu| = 1) whose pause is the drain (τ),
  // where D(τ) is that overshoot area. The FIR alone (S within [0, 1]) needs nothing.
  if (!(filter_.overshoot_s() > 0.0) || !(b.m.path_tolerance_mm > 0.0)) return;
  Element e;
  e.kind = ElementKind::Stop;
  e.seq = b.seq;
  e.t0 = e.t1 = b.t1;
  e.s0 = e.s1 = b.s1;
  e.tol_mm = b.m.path_tolerance_mm;
  e.turn = 1.0;
  e.pause0 = filter_.tau_s();
  e.vmax = b.vmax;
  e.v100 = b.v100;
  push_element(e);
}

bool TolerancePlanner::lookahead_enough() const {
  if (ended_ || window_.size() >= cfg_.capacity) return true;
  const double tau = filter_.tau_s();
  const Block& f = window_.front();
  // A chain of arcs is cut into pieces whole, when its first block is handed on.
  const double f_t1 = emit_horizon_t(f);
  double need = f_t1 + 2.0 * tau;
  // Near-tangent corners waiting for their claim (assign_claims, through τ past a decision)
  // need the blocks within τ after them.
  const double reach = claim_candidates_ > 0 ? 2.0 * tau : tau;
  double horizon = f_t1 + tau;  // what the decisions emitting f see, and zones reaching f
  for (const Element& e : elems_)
    if (!e.decided && e.t0 < f_t1 + tau) {
      // A group planned for a later block's tolerance is decided whole, from its last element.
      const double t1 = e.untol_for != 0 ? std::max(e.t1, e.group_t1) : e.t1;
      need = std::max(need, t1 + reach);
      horizon = std::max(horizon, t1 + tau);
    }
  // A chunk being gathered spans at most τ: it is closed before it is needed.
  if (run_.open && run_.chunk.t0 < f_t1 + tau) need = std::max(need, run_.chunk.t0 + 2.0 * tau);
  // A corner or arc without a tolerance that these decisions can see, or whose zone (at most τ
  // of travel before it) can reach f, is first planned or let go (plan_untoleranced,
  // drop_untoleranced): the window must reach its end, and every one still waiting ends past
  // the window's end.
  if (!untoleranced_.empty() && untoleranced_.front().t0 <= horizon) return false;
  return window_.back().t1 >= need;
}

double TolerancePlanner::zone_back(double s_from, double time_s, double cap) const {
  if (!(cap < kInf) || time_s <= 0.0) return s_from;
  auto it = std::lower_bound(window_.begin(), window_.end(), s_from,
                             [](const Block& b, double s) { return b.s1 < s; });
  if (it == window_.end()) return s_from;
  double r = time_s;
  double s = s_from;
  for (auto i = static_cast<std::ptrdiff_t>(it - window_.begin()); i >= 0; --i) {
    const Block& b = window_[static_cast<std::size_t>(i)];
    const double w = std::min(cap, b.vmax);
    const double len = std::min(s, b.s1) - b.s0;
    if (len / w >= r) return std::min(s, b.s1) - r * w;
    r -= len / w;
    s = b.s0;
    if (i == 0) break;
    const Block& p = window_[static_cast<std::size_t>(i - 1)];
    if (p.stop_after) return s;
    r -= p.dwell_after_s;
    if (r <= 0.0) return s;
  }
  return s;
}

double TolerancePlanner::zone_fwd(double s_from, double time_s, double cap) const {
  if (!(cap < kInf) || time_s <= 0.0) return s_from;
  auto it = std::upper_bound(window_.begin(), window_.end(), s_from,
                             [](double s, const Block& b) { return s < b.s1; });
  double r = time_s;
  double s = s_from;
  for (; it != window_.end(); ++it) {
    const Block& b = *it;
    const double w = std::min(cap, b.vmax);
    const double from = std::max(s, b.s0);
    const double len = b.s1 - from;
    if (len / w >= r) return from + r * w;
    r -= len / w;
    s = b.s1;
    if (b.stop_after) return s;
    r -= b.dwell_after_s;
    if (r <= 0.0) return s;
  }
  return s;
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

TolerancePlanner::SameRun TolerancePlanner::same_run(const Element& e, ZoneRange r) const {
  // As range_weight and range_decided count them: undecided past the decided prefix, else
  // decided (and both ways when decided out of order).
  SameRun same;
  r = parted(r, e);
  for (std::size_t i = r.first; i < r.last; ++i) {
    const Element& f = elems_[i];
    if (f.kind != ElementKind::Run || f.run_id != e.run_id) continue;
    if (i >= decided_prefix_) same.weight += f.weight;
    same.weight_all += f.weight;
  }
  same.decided = range_decided(r, e, &e);
  return same;
}

TolerancePlanner::ZoneRange TolerancePlanner::zone_range(double z0, double z1) const {
  // Every element that reaches into [z0, z1]: elements are in path order, so a range.
  auto first = std::lower_bound(elems_.begin(), elems_.end(), z0 - 1e-9,
                                [](const Element& f, double z) { return f.s1 <= z; });
  auto last = std::lower_bound(first, elems_.end(), z1 + 1e-9,
                               [](const Element& f, double z) { return f.s0 < z; });
  return {static_cast<std::size_t>(first - elems_.begin()),
          static_cast<std::size_t>(last - elems_.begin())};
}

bool TolerancePlanner::same_element(const Element& f, const Element& e) {
  return &f == &e || (f.kind == e.kind && f.seq == e.seq);  // e may be a copy of f
}

TolerancePlanner::ZoneRange TolerancePlanner::parted(ZoneRange r, const Element& e) const {
  // A full stop (Element::stopped) in the range parts it: no window holds both sides, so only
  // the elements on e's side share e's zone.
  for (std::size_t i = r.first; i < r.last; ++i) {
    const Element& g = elems_[i];
    if (!g.stopped || same_element(g, e)) continue;
    if (g.s1 <= e.s0 + 1e-9) {
      r.first = i + 1;
    } else if (g.s0 >= e.s1 - 1e-9) {
      r.last = i;
      break;
    }
  }
  r.last = std::max(r.last, r.first);
  return r;
}

double TolerancePlanner::range_weight(ZoneRange r) const {
  const std::size_t from = std::max(r.first, decided_prefix_);
  if (from >= r.last) return 0.0;
  const double end = r.last == elems_.size() ? weight_total_ : elems_[r.last].cum;
  return end - elems_[from].cum;
}

double TolerancePlanner::range_weight_all(ZoneRange r) const {
  if (r.first == r.last) return 0.0;
  const double end = r.last == elems_.size() ? weight_total_ : elems_[r.last].cum;
  return end - elems_[r.first].cum;
}

bool TolerancePlanner::counts_decided(const Element& f, const Element& e) {
  // (e is marked decided while it is being decided.) One decided out of path order counts both
  // ways, weight (range_weight) and err.
  return f.decided && &f != &e && f.reach1 > e.s0 - 1e-9 && f.reach0 < e.s1 + 1e-9;
}

double TolerancePlanner::err_seen(const Element& f, const Element& e) {
  if (f.slower_ends()) {
    if (e.s0 >= f.s1 - 1e-9) return f.ends[1].err;
    if (e.s1 <= f.s0 + 1e-9) return f.ends[0].err;
  }
  return f.err;
}

TolerancePlanner::Decided TolerancePlanner::range_decided(ZoneRange r, const Element& e,
                                                          const Element* run_of) const {
  // The undecided elements besides e start at the range's first past the prefix (e aside):
  // elements are in path order, so a decided one reaches them when its zone reaches that one
  // (one decided out of order counts as reaching them).
  std::size_t u = std::max(r.first, decided_prefix_);
  if (u < r.last && &elems_[u] == &e) ++u;
  const double undecided_from = u < r.last ? elems_[u].s0 - 1e-9 : kInf;
  const std::size_t end =
      decided_count_ > decided_prefix_ ? r.last : std::min(r.last, decided_prefix_);
  Decided d;
  for (std::size_t i = r.first; i < end; ++i) {
    const Element& f = elems_[i];
    if (!counts_decided(f, e)) continue;
    if (run_of != nullptr && !(f.kind == ElementKind::Run && f.run_id == run_of->run_id)) continue;
    // The part of its share it uses, in e's share: an instant with both is within the larger
    // tolerance of the two (each element's is the smallest around it), and parts add to 1.
    const double seen = err_seen(f, e);
    const double err = f.share == e.share || !(f.share > 0.0) ? seen : seen / f.share * e.share;
    d.all += err;
    if (i >= decided_prefix_ || f.reach1 > undecided_from) d.shared += err;
  }
  return d;
}

void TolerancePlanner::extend_decided_prefix() {
  while (decided_prefix_ < elems_.size() && elems_[decided_prefix_].decided) ++decided_prefix_;
}

TolerancePlanner::ZoneRange TolerancePlanner::zone_range_from(ZoneRange hint, double z0,
                                                              double z1) const {
  // zone_range's partition points walked from a nearby range's (the zones of a bisection close
  // in on one range): the same indices as the binary searches.
  const std::size_t n = elems_.size();
  const double a = z0 - 1e-9, b = z1 + 1e-9;
  std::size_t f = hint.first, l = hint.last;
  while (f < n && elems_[f].s1 <= a) ++f;
  while (f > 0 && !(elems_[f - 1].s1 <= a)) --f;
  l = std::max(l, f);
  while (l < n && elems_[l].s0 < b) ++l;
  while (l > f && !(elems_[l - 1].s0 < b)) --l;
  return {f, l};
}

const TolerancePlanner::ZoneMemo& TolerancePlanner::zone_values(ZoneMemo& memo, ZoneRange r,
                                                                const Element& e,
                                                                bool with_claims) const {
  if (!memo.valid || !(r == memo.range)) {
    memo.range = r;
    memo.valid = true;
    r = parted(r, e);
    memo.weight = range_weight(r);
    memo.weight_all = range_weight_all(r);
    memo.decided = range_decided(r, e);
    memo.claims = with_claims ? range_claims(r) : 0.0;
  }
  return memo;
}

template <class Load, class Guess>
std::optional<double> TolerancePlanner::narrowed_speed_in_zones(double vmax, double share,
                                                                double s0, double s1, double t,
                                                                ZoneRange hi_r, Load& load,
                                                                Guess& guess) const {
  // The same halvings, all 40 at once: they visit the points k·δ, δ = vmax/2^40, and end on
  // the largest k whose load fits (0 when none). The bracket is narrowed first, by loads at
  // speeds that fit or do not (monotone: a speed below one that fits fits): just below the
  // root of the largest zone's load (guess, at vmax), then from the largest speed known to
  // fit, the root of its zone's load or the speed where the next element enters the zone
  // (the load jumps there), whichever comes first, just below and just above it. Once the
  // fitting speed is known within δ, k is read from it and confirmed by two loads, as
  // largest_speed_in_zones does (its halvings at it = 0); otherwise those halvings run.
  double fits_up_to = 0.0, fails_from = vmax;
  ZoneRange hint = hi_r;
  auto fits = [&](double v) {
    if (v <= fits_up_to) return true;
    if (v >= fails_from) return false;
    hint = zone_range_from(hint, s0 - v * t, s1 + v * t);
    if (load(v, hint) <= share) {
      fits_up_to = v;
      return true;
    }
    fails_from = v;
    return false;
  };
  constexpr double kNear = 1e-12;
  const double g = guess(hint);
  if (g > 0.0 && g < vmax) fits(g * (1.0 - kNear));
  for (int round = 0; round < 16 && fails_from - fits_up_to > 0.0; ++round) {
    const double a = fits_up_to;
    const ZoneRange r = zone_range_from(hint, s0 - a * t, s1 + a * t);
    // zone_range's tests: elems_[first − 1] joins once s0 − v·t > its s1 + 1e-9 no longer
    // holds, elems_[last] once s1 + v·t > its s0 − 1e-9. Where, to the rounding, is
    // found on the tests themselves: the largest speed without it, the smallest with it.
    const Element* before = r.first > 0 ? &elems_[r.first - 1] : nullptr;
    const Element* after = r.last < elems_.size() ? &elems_[r.last] : nullptr;
    auto joins = [&](double v) {  // zone_range_from's tests, on these two elements
      const double z0 = s0 - v * t, z1 = s1 + v * t;
      return (before != nullptr && !(before->s1 <= z0 - 1e-9)) ||
             (after != nullptr && after->s0 < z1 + 1e-9);
    };
    double enter = kInf;
    if (before != nullptr) enter = std::min(enter, (s0 - 1e-9 - before->s1) / t);
    if (after != nullptr) enter = std::min(enter, (after->s0 - 1e-9 - s1) / t);
    const double root = guess(r);
    if (root < enter) {  // the root of this zone's load comes first
      if (!(root > a) || !(root < fails_from)) break;
      fits(root * (1.0 - kNear));
      fits(root * (1.0 + kNear));
      break;
    }
    if (!(enter > a) || !(enter < fails_from)) break;
    double below = std::max(a, enter * (1.0 - 1e-9)), above = enter * (1.0 + 1e-9);
    if (joins(below) || !joins(above)) break;
    // joins is monotone in v: the pair is the one float step where it turns true, which
    // first_joining_speed finds from the roundings of its tests; checked here, else halved.
    if (const double v = first_joining_speed(s0, s1, t, before ? &before->s1 : nullptr,
                                             after ? &after->s0 : nullptr);
        v > below && v <= above && joins(v) && !joins(float_down(v))) {
      below = float_down(v);
      above = v;
    }
    for (int it = 0; it < 40 && float_up(below) < above; ++it) {
      const double mid = 0.5 * (below + above);
      (joins(mid) ? above : below) = mid;
    }
    fits(below);
    if (!fits(above)) break;
  }
  const double delta = std::ldexp(vmax, -40), kmax = std::ldexp(1.0, 40) - 1.0;
  const double k = std::floor(fits_up_to / delta);
  if (fails_from - fits_up_to <= delta && k >= 0.0 && k <= kmax &&
      (k == 0.0 || fits(0.0 + k * delta)) && (k == kmax || !fits(0.0 + (k + 1.0) * delta)))
    return 0.0 + k * delta;
  return std::nullopt;
}

template <class Load, class Guess>
double TolerancePlanner::largest_speed_in_zones(double vmax, double share, double s0, double s1,
                                                double t, Load&& load, Guess&& guess) const {
  // largest_speed_within, the zone [s0 − v·t, s1 + v·t] found for each speed. Zones grow with v
  // (v·t and the sums are monotone in floating point), so when the ranges at both ends of the
  // bracket agree every speed between has that range: it is not searched again. The loads and
  // comparisons are the same, so is the result, bit for bit.
  ZoneRange hi_r = zone_range(s0 - vmax * t, s1 + vmax * t);
  if (load(vmax, hi_r) <= share) return vmax;
  if (const std::optional<double> v =
          narrowed_speed_in_zones(vmax, share, s0, s1, t, hi_r, load, guess))
    return *v;
  ZoneRange lo_r = zone_range_from(hi_r, s0 - 0.0 * t, s1 + 0.0 * t);
  double lo = 0.0, hi = vmax;
  for (int it = 0; it < 40; ++it) {
    if (lo_r == hi_r) {
      // The halvings left visit the points lo + k·δ, δ = (hi − lo)/2^m, all exact in floating
      // point, and end on the largest k (0 or one whose load fits: the load is monotone in v).
      // guess(range), the speed where the load reaches the share, names k; two loads confirm it
      // (otherwise the halvings go on).
      const int m = 40 - it;
      const double delta = std::ldexp(hi - lo, -m), kmax = std::ldexp(1.0, m) - 1.0;
      const double k = std::floor((guess(lo_r) - lo) / delta);
      if (k >= 0.0 && k <= kmax && (k == 0.0 || load(lo + k * delta, lo_r) <= share) &&
          (k == kmax || !(load(lo + (k + 1.0) * delta, lo_r) <= share)))
        return lo + k * delta;
      if (!(k >= 0.0) && !(load(lo + delta, lo_r) <= share)) return lo;  // k = 0
      if (k > kmax && load(lo + kmax * delta, lo_r) <= share) return lo + kmax * delta;
    }
    const double mid = 0.5 * (lo + hi);
    const ZoneRange r = lo_r == hi_r ? lo_r : zone_range_from(hi_r, s0 - mid * t, s1 + mid * t);
    if (load(mid, r) <= share) {
      lo = mid;
      lo_r = r;
    } else {
      hi = mid;
      hi_r = r;
    }
  }
  return lo;
}

double TolerancePlanner::tolerance_near(const Element& e) const {
  const double tau = filter_.tau_s();
  // The smallest among the elements that can share a window with e and the blocks the
  // interpolator is in while the filter still holds e (each judged by its own). A full stop
  // decided at a corner (Element::stopped) parts e from what lies beyond it: the filter drains
  // there, and the pause belongs to the block before it.
  const StopsBeside stops = stops_beside(e);
  const double t_from = stops.before != nullptr ? stops.before->t1 : -kInf;
  const double t_until = stops.after != nullptr ? stops.after->t0 : kInf;
  // The times are at the fastest speeds; an arc decided with a cap wholly between s_a and s_b
  // takes at least its length at that cap (its zone holds it), which parts e further from what
  // lies beyond it: a window that holds samples of both spans that time too (docs/
  // tolerance.md, "Tolerances near"). Summed only for a tolerance that would lower e's.
  auto extra_s = [this](double s_a, double s_b) {
    double extra = 0.0;
    for (const Element& g : elems_) {
      if (g.s0 > s_b + 1e-9) break;
      if (g.decided && g.kind == ElementKind::Arc && g.cap > 0.0 && g.cap < kInf &&
          g.s0 >= s_a - 1e-9 && g.s1 <= s_b + 1e-9)
        extra += std::max(0.0, (g.s1 - g.s0) / g.cap - (g.t1 - g.t0));
    }
    return extra;
  };
  double tol = e.tol_mm;
  for (const Element& f : elems_) {
    if (!(f.tol_mm < tol) || !(f.t1 > t_from && f.t0 < t_until)) continue;
    const double gap = f.t0 > e.t1 ? f.t0 - e.t1 + extra_s(e.s1, f.s0)
                                   : (e.t0 > f.t1 ? e.t0 - f.t1 + extra_s(f.s1, e.s0) : 0.0);
    if (gap < tau) tol = f.tol_mm;
  }
  for (const Block& b : window_)
    if (b.m.path_tolerance_mm > 0.0 && b.m.path_tolerance_mm < tol && b.t1 >= e.t0 &&
        b.t0 < e.t1 + tau && b.t1 > t_from && b.t0 < t_until &&
        (!(b.t0 > e.t1) || b.t0 + extra_s(e.s1, b.s0) < e.t1 + tau))
      tol = b.m.path_tolerance_mm;
  return tol;
}

void TolerancePlanner::assign_claims(double t_until) {
  const double tau = filter_.tau_s();
  for (; claim_cursor_ < elems_.size() && elems_[claim_cursor_].t0 <= t_until; ++claim_cursor_) {
    Element& g = elems_[claim_cursor_];
    if (g.claim_state != Element::Claim::Unassigned) continue;
    g.claim_state = Element::Claim::Share;
    if (!(g.kind == ElementKind::Corner && g.turn <= kClaimTurn)) continue;
    --claim_candidates_;
    // The claim must hold against the tolerance of every block the filter holds g in: those
    // blocks must be in the window.
    if (!ended_ && window_.back().t1 < g.t1 + tau) continue;
    const double tol = tolerance_near(g);
    // The mismatch at a sample where g is active: at most M times the fastest block within reach
    // (g has no cap).
    const double share = share_of(tol) - mismatch_reserve(g, tol).ceiling_mm();
    // Claims active with g lie within τ of it; those after g are assigned after it and count g.
    double near = 0.0;
    for (std::size_t i = claim_cursor_; i-- > 0 && elems_[i].t1 >= g.t0 - tau;)
      if (elems_[i].claim_state == Element::Claim::Claimant) near += elems_[i].claim;
    // At its fastest speed (no cap: only the smallest turns, or where no override can run the
    // path faster than 100 %), else at 100 % feed with its zone capped there.
    for (const double v : {g.vmax, std::min(g.vmax, g.v100)}) {
      if (v == g.vmax && g.turn > kClaimFreeTurn && g.v100 < g.vmax) continue;
      const double claim = v * corner_moment(g.pause0) * g.turn;
      if (near + claim > 0.5 * share) continue;
      g.claim_state = Element::Claim::Claimant;
      g.claim = claim;
      g.claim_cap = v < g.vmax ? v : kInf;
      ++claimants_;
      break;
    }
  }
}

double TolerancePlanner::zone_claims(double z0, double z1) const {
  if (claimants_ == 0) return 0.0;
  return range_claims(zone_range(z0, z1));
}

double TolerancePlanner::range_claims(ZoneRange r) const {
  if (claimants_ == 0) return 0.0;
  const double tau = filter_.tau_s();
  const auto first = elems_.begin() + static_cast<std::ptrdiff_t>(r.first);
  const auto last = elems_.begin() + static_cast<std::ptrdiff_t>(r.last);
  double best = 0.0, sum = 0.0;
  auto lo = first;
  for (auto it = first; it != last; ++it) {
    if (it->claim_state != Element::Claim::Claimant) continue;
    sum += it->claim;
    for (; lo->t1 < it->t0 - tau; ++lo)
      if (lo->claim_state == Element::Claim::Claimant) sum -= lo->claim;
    best = std::max(best, sum);
  }
  return best;
}

void TolerancePlanner::decide(Element& e) {
  if (weigh_depth_ == 0) assign_claims(e.t1 + filter_.tau_s());
  const double tol = tolerance_near(e);
  // The servo mismatch's part (speed_error_s) is kept beside each load, by the speeds e's
  // samples can see (MismatchReserve): load(v) + reserve(v) <= share.
  const double share = share_of(tol);
  const MismatchReserve res = mismatch_reserve(e, tol);
  // Sharing: an element f whose contribution overlaps e's in time lies in e's zone (the speed
  // is at most e's cap there for the zone's time, and past it e no longer counts). Each element
  // takes share·w_e/W_e, W_e the weight (corner |Δu|, arc 1) of everything in its zone: any set
  // of elements active at one instant adds up to at most the share.
  // W(v) over a zone taken as s ∓ v·t: it holds the true zone (τ − P of time at speeds <= v),
  // so W is never undercounted. load(v) = error·W grows with v: the largest v <= vmax with
  // load(v) <= share, by bisection (largest_speed_in_zones).
  e.decided = true;
  e.cap = kInf;
  e.err = 0.0;
  e.share = share;
  if (e.claim_state == Element::Claim::Claimant) {  // its claim is counted by every neighbour
    e.pause = e.pause0;                             // (err 0: its claim counts instead)
    e.reach0 = e.s0;
    e.reach1 = e.s1;
    e.z0 = e.z1 = e.s0;
    if (e.claim_cap < kInf) {  // the blocks its window can hold take its cap
      e.cap = e.claim_cap;
      const double zt = std::max(filter_.zone_floor_s(), filter_.tau_s() - e.pause0);
      e.z0 = zone_back(e.s0, zt, e.cap);
      e.z1 = zone_fwd(e.s1, zt, e.cap);
    }
    return;
  }
  // Every other element takes the claims that can be active beside it off its share:
  // (share − claims)·w_e/W_e, so that with the claimants any instant stays within the share.
  switch (e.kind) {
    case ElementKind::Arc:
      if (weigh_depth_ == 0)
        decide_arc_weighing(e, share, res);
      else
        decide_arc_beside_claims(e, share, res);
      return;
    case ElementKind::Run:
      decide_run(e, share, res);
      part_zone(e);
      return;
    case ElementKind::Corner:
    case ElementKind::Stop:
      decide_corner(e, share, res);
      part_zone(e);
      return;
  }
}

void TolerancePlanner::decide_arc(Element& e, double share, const MismatchReserve& res) const {
  const double tau = filter_.tau_s();
  // κ·v²·σ²/2 <= (share − reserve)/W
  ZoneMemo memo;
  const double a = 0.5 * e.kappa * filter_.variance_s2();
  auto load = [&](double v, ZoneRange r) {
    return zone_load(a * v * v, 1.0, zone_values(memo, r, e, false)) + res.at(v, v < e.vmax);
  };
  auto guess = [&](ZoneRange r) {
    const double left = std::max(0.0, zone_allotment(share, 1.0, zone_values(memo, r, e, false)));
    return res.m_s > 0.0 ? res.root(a, 0.0, left) : std::sqrt(left / a);
  };
  double v = largest_speed_in_zones(e.vmax, share, e.s0, e.s1, tau, load, guess);
  e.comp_speed = 0.0;
  e.err = a * v * v;
  e.ends = {};
  if (v < e.vmax && precomp_) {
    double err = 0.0;
    std::array<Element::EndCap, 2> ends{};
    const double vc = precomp_arc_speed(e, share - res.ceiling_mm(), v, err, &ends);
    if (vc > v) {
      v = vc;
      e.comp_speed = vc;
      e.err = err;
      e.ends = ends;
    }
  }
  // A pre-compensated arc keeps its zone even at its fastest speed: its term holds for lines at
  // most v_p beside it (a faster line into it raises the term about as its speed; docs/
  // tolerance-arc-ends.md, "Speed steps at an arc's ends"), so they are capped there too.
  if (v < e.vmax || e.comp_speed > 0.0) e.cap = v;
  e.reach0 = e.s0 - v * tau;
  e.reach1 = e.s1 + v * tau;
  e.z0 = zone_back(e.s0, tau, e.cap);
  e.z1 = zone_fwd(e.s1, tau, e.cap);
  part_zone(e);
}

TolerancePlanner::StopsBeside TolerancePlanner::stops_beside(const Element& e) const {
  // Elements are in path order: the last stop before e and the first after it.
  StopsBeside r;
  for (const Element& g : elems_) {
    if (!g.stopped || same_element(g, e)) continue;
    if (g.s1 <= e.s0 + 1e-9) {
      r.before = &g;
    } else if (g.s0 >= e.s1 - 1e-9) {
      r.after = &g;
      break;
    }
  }
  return r;
}

void TolerancePlanner::part_zone(Element& e) const {
  // A full stop (Element::stopped) before or after e parts it from what lies past the stop: no
  // window holds both, so e's zone (where its cap holds) and its reach end there.
  const StopsBeside stops = stops_beside(e);
  if (stops.before != nullptr) {
    e.z0 = std::max(e.z0, stops.before->s1);
    e.reach0 = std::max(e.reach0, stops.before->s1);
  }
  if (stops.after != nullptr) {
    e.z1 = std::min(e.z1, stops.after->s0);
    e.reach1 = std::min(e.reach1, stops.after->s0);
  }
  for (Element::EndCap& c : e.ends) {
    if (stops.before != nullptr) c.lo = std::max(c.lo, stops.before->s1);
    if (stops.after != nullptr) c.hi = std::min(c.hi, stops.after->s0);
  }
}

double TolerancePlanner::precomp_arc_speed(const Element& e, double share, double floor,
                                           double& err,
                                           std::array<Element::EndCap, 2>* ends_out) const {
  if (!(e.radius > 0.0) || !(e.sweep > 0.0)) return 0.0;
  const double tau = filter_.tau_s(), L = e.s1 - e.s0;
  // The isolated arc's term (transitions at its ends, the ramp's transient) against its share
  // share/W, W the weight of its zone, as the curvature term was; the speed where A(ωT) falls
  // to ArcCompensation::kMinGain at most. The term grows with the speed: bisection.
  // within(v): error_mm(v)·W(v) <= share, decided without finishing the simulation when a
  // part of it already exceeds (error_within).
  // The term from the residual table (a bound of the simulation, docs/tolerance.md "Planning
  // cost") where it covers the arc, else simulated.
  ZoneMemo memo;
  // A chain of arcs (seq_last > seq) is long: a window that holds some of it lies within τ of
  // travel of its start, or of its end, or on it, and holds only what those three ranges hold.
  // Its term (err) is charged in each, so its allotment is the least of the three instead of
  // that of its whole zone: the elements beside its start and those beside its end do not
  // share it with each other (docs/tolerance.md, "Arcs on one circle").
  const bool chain = e.seq_last > e.seq;
  std::array<ZoneMemo, 3> ends{};
  auto chain_allotment = [&](double v) {
    const double reach = v * tau;
    const std::array<std::pair<double, double>, 3> ranges{
        {{e.s0 - reach, e.s0 + reach}, {e.s0, e.s1}, {e.s1 - reach, e.s1 + reach}}};
    double least = kInf;
    for (std::size_t k = 0; k < 3; ++k)
      least = std::min(
          least, zone_allotment(share, 1.0,
                                zone_values(ends[k], zone_range(ranges[k].first, ranges[k].second),
                                            e, false)));
    return least;
  };
  // The arc's error at v within `allotment` (zone_allotment, W = w): a near circle's extra term
  // off it (a circle's is 0), the circle's term at most the allotment wherever the answer is
  // yes.
  // A servo mismatch moves the table by the command's offset too (offset_mismatch_mm).
  auto mismatch_at = [&](double v, bool cap) {  // offset_mismatch_mm, or its cheap cap
    return std::invoke(
        cap ? &ArcPrecompCheck::offset_mismatch_cap_mm : &ArcPrecompCheck::offset_mismatch_mm,
        *precomp_, e.radius, e.sweep, L, v, cfg_.speed_error_s, cfg_.step_error,
        cfg_.fir_variation);
  };
  auto fits = [&](double v, double allotment, double w) {
    auto mismatch_mm = [&](bool cap) { return mismatch_at(v, cap); };
    if (cfg_.speed_error_s > 0.0 && !(e.spiral > 0.0) && residual_->covers(e.sweep, L, v)) {
      // offset_mismatch_mm (>= 0) bracketed first, the same answer at less cost: an arc that
      // does not fit without it does not fit, one that fits with its cheap cap fits.
      const double bound = residual_->error_bound_mm(*precomp_, e.radius, e.sweep, L, v) * w;
      if (!(bound <= allotment * w)) return false;
      const double cap_left = (allotment - mismatch_mm(true)) * w;
      if (cap_left > 0.0 && bound <= cap_left) return true;
      const double left = (allotment - mismatch_mm(false)) * w;
      return left > 0.0 && bound <= left;
    }
    const double mine = allotment - (cfg_.speed_error_s > 0.0 ? mismatch_mm(false) : 0.0);
    const double left = (e.spiral > 0.0 ? mine - precomp_->spiral_mm(e.radius - e.spiral, e.radius,
                                                                     e.sweep, L, v, mine)
                                        : mine) *
                        w;
    if (!(left > 0.0)) return false;
    if (residual_->covers(e.sweep, L, v))
      return residual_->error_bound_mm(*precomp_, e.radius, e.sweep, L, v) * w <= left;
    return precomp_->error_within(e.radius, e.sweep, L, v, w, left);
  };
  auto within = [&](double v) {
    if (chain) return fits(v, chain_allotment(v), 1.0);
    const ZoneRange r = memo.valid ? zone_range_from(memo.range, e.s0 - v * tau, e.s1 + v * tau)
                                   : zone_range(e.s0 - v * tau, e.s1 + v * tau);
    const ZoneMemo& z = zone_values(memo, r, e, false);
    return fits(v, zone_allotment(share, 1.0, z), z.weight);
  };
  // Where the answer is yes, the arc's error (its term and a near circle's extra) is within
  // its allotment at that speed: the bound it leaves (err).
  auto allotted = [&](double v) {
    if (chain) return chain_allotment(v);
    return zone_allotment(share, 1.0,
                          zone_values(memo, zone_range(e.s0 - v * tau, e.s1 + v * tau), e, false));
  };
  const double vlim = std::min(e.vmax, precomp_->speed_limit_mm_s(e.sweep, L));
  if (!(vlim > floor)) return 0.0;
  if (within(vlim)) {
    err = allotted(vlim);
    return vlim;
  }
  double lo = floor, hi = vlim;  // lo: no better than the curvature cap until shown
  for (int it = 0; it < 10; ++it) {
    const double mid = 0.5 * (lo + hi);
    (within(mid) ? lo : hi) = mid;
  }
  err = allotted(lo);
  // Its middle faster than its ends: a chain, or an arc cut at zone boundaries (one turn at
  // most) that is a circle (a near circle's extra term is not the ramps').
  if ((chain || (e.split && !(e.spiral > 0.0))) && ends_out != nullptr && lo > floor) {
    double mid_err = 0.0;
    // Away from its ends the arc's error is the ramps' transient on the steady arc (ramps_mm:
    // the whole error there, the steady correction's included), simulated, or (`exact` false)
    // bounded by the table where it covers.
    auto fits_middle = [&](double v, double allotment, bool exact) {
      const double mine = allotment - (cfg_.speed_error_s > 0.0 ? mismatch_at(v, false) : 0.0);
      if (!(mine > 0.0)) return false;
      return (!exact && residual_->covers(e.sweep, L, v)
                  ? residual_->ramps_bound_mm(*precomp_, e.radius, e.sweep, L, v)
                  : precomp_->ramps_mm(e.radius, e.sweep, L, v)) <= mine;
    };
    const double v_mid = slower_ends(e, lo, vlim, share, fits, fits_middle, *ends_out, mid_err);
    if (v_mid > 0.0) {
      err = std::max({mid_err, (*ends_out)[0].err, (*ends_out)[1].err});
      return v_mid;
    }
  }
  return lo;
}

template <class Fits, class FitsMiddle>
double TolerancePlanner::slower_ends(const Element& e, double v_one, double vlim, double share,
                                     Fits& fits, FitsMiddle& fits_middle,
                                     std::array<Element::EndCap, 2>& ends, double& mid_err) const {
  // An arc (a chain, or one block) at one speed v_one takes the allotment of its whole zone, or
  // a chain the least of its start's, its end's and its own ranges', its whole term charged in
  // each (precomp_arc_speed). Its middle may run faster: a window wholly on the arc holds
  // nothing else (its allotment is the whole share), and the arc's error there is the ramps'
  // transient (fits_middle), not its ends' transitions.
  // Each end then runs at the speed its own range allows over 2τ + kCompEndSamples samples of
  // travel on the arc (a window holding the end's transition, its rows, or the ramp from or to
  // rest there, holds no sample of the ramp between the end's speed and the middle's) and τ of
  // travel beside it, as an arc planned at that speed: its term at that speed is charged in its
  // range, and the elements beyond that end see that end's allotment only (err_seen).
  const double tau = filter_.tau_s(), L = e.s1 - e.s0;
  // The chain's own path an end at v takes.
  auto end_stretch = [&](double v) {
    return v * (2.0 * tau + kCompEndSamples * filter_.period_s());
  };
  // At least one end is slower (both as fast as the middle would fit the whole zone at it) and
  // no slower than v_one: too short for that, the arc runs at one speed.
  if (!(end_stretch(v_one) < L)) return 0.0;
  const double v_gain = v_one * (1.0 + kSlowerEndsGain);
  if (!fits_middle(v_gain, share, false)) return 0.0;  // its allotment is at most the share
  ZoneMemo mid_memo;
  const double mid_allot = zone_allotment(
      share, 1.0, zone_values(mid_memo, zone_range(e.s0 + 1e-6, e.s1 - 1e-6), e, false));
  auto largest = [&](double lo, double hi, auto ok) {
    if (ok(hi)) return hi;
    for (int it = 0; it < 10; ++it) {
      const double mid = 0.5 * (lo + hi);
      (ok(mid) ? lo : hi) = mid;
    }
    return lo;
  };
  // The middle's speed by the table first (cheap: most arcs are then too short for their ends).
  double v_mid = largest(v_one, vlim, [&](double v) { return fits_middle(v, mid_allot, false); });
  if (!(v_mid > v_gain)) return 0.0;
  std::array<ZoneMemo, 2> memos{};
  auto end_allot = [&](std::size_t k, double v) {
    const double at = k == 0 ? e.s0 : e.s1, reach = v * tau;
    return zone_allotment(share, 1.0,
                          zone_values(memos[k], zone_range(at - reach, at + reach), e, false));
  };
  // The ends' speeds under a middle at vm, and the arc's path the slower ends and the ramps to
  // them take.
  auto plan_ends = [&](double vm, std::array<double, 2>& v_end) {
    double need = 0.0;
    for (std::size_t k = 0; k < 2; ++k) {
      v_end[k] = largest(v_one, vm, [&](double v) { return fits(v, end_allot(k, v), 1.0); });
      if (v_end[k] < vm) need += end_stretch(v_end[k]) + braking_length_mm(vm, v_end[k], vm);
    }
    return need;
  };
  std::array<double, 2> v_end{};
  if (!(plan_ends(v_mid, v_end) < L)) return 0.0;
  // Then as fast as the simulation allows (the table's bound is kMargin above it), where the
  // ends still fit.
  const double v_sim =
      largest(v_mid, vlim, [&](double v) { return fits_middle(v, mid_allot, true); });
  if (std::array<double, 2> v_end_sim{}; v_sim > v_mid && plan_ends(v_sim, v_end_sim) < L)
    v_mid = v_sim, v_end = v_end_sim;
  for (std::size_t k = 0; k < 2; ++k) {
    Element::EndCap& c = ends[k];
    c.err = end_allot(k, v_end[k]);
    if (!(v_end[k] < v_mid)) continue;
    c.cap = v_end[k];
    c.lo = k == 0 ? zone_back(e.s0, tau, c.cap) : e.s1 - end_stretch(c.cap);
    c.hi = k == 0 ? e.s0 + end_stretch(c.cap) : zone_fwd(e.s1, tau, c.cap);
  }
  mid_err = mid_allot;
  return v_mid;
}

void TolerancePlanner::decide_arc_beside_claims(Element& e, double share,
                                                const MismatchReserve& res) const {
  decide_arc(e, share, res);
  if (claimants_ == 0) return;
  // The claims within the zone of the cap found without them: the final cap is no faster, so
  // its zone holds no more of them.
  const double tau = filter_.tau_s();
  const double v0 = e.cap < kInf ? e.cap : e.vmax;
  const double claims = zone_claims(e.s0 - v0 * tau, e.s1 + v0 * tau);
  if (!(claims > 0.0)) return;
  decide_arc(e, std::max(share - claims, res.max_mm + 0.25 * (share - res.max_mm)), res);
}

void TolerancePlanner::decide_run(Element& e, double share, const MismatchReserve& res) const {
  const double tau = filter_.tau_s();
  // (κ·v²·σ²/2 + δ·v·M₁)·W <= share, κ and δ the largest of the run's chunks within reach (a
  // filter window over two chunks sees both), W counting the run once, by this chunk's weight.
  double kappa = e.kappa, delta = e.delta;
  const double w0 = e.s0 - e.vmax * tau, w1 = e.s1 + e.vmax * tau;
  for (const Element& f : elems_)
    if (f.kind == ElementKind::Run && f.run_id == e.run_id && f.s1 > w0 - 1e-9 &&
        f.s0 < w1 + 1e-9) {
      kappa = std::max(kappa, f.kappa);
      delta = std::max(delta, f.delta);
    }
  auto own = [&](double v) {
    return 0.5 * kappa * v * v * filter_.variance_s2() + delta * v * filter_.abs_moment_s();
  };
  // The zone's values with the run counted once, by this chunk: its other chunks' weights and
  // errs out (kept for the last range asked for, as memo is).
  ZoneMemo memo, once;
  auto values = [&](ZoneRange r) -> const ZoneMemo& {
    if (memo.valid && r == memo.range) return once;
    const ZoneMemo& z = zone_values(memo, r, e, true);
    const SameRun same = same_run(e, r);
    once = z;
    once.weight = z.weight - same.weight + e.weight;
    once.weight_all = z.weight_all - same.weight_all + e.weight;
    once.decided.all -= same.decided.all;
    once.decided.shared -= same.decided.shared;
    return once;
  };
  auto load = [&](double v, ZoneRange r) {
    return zone_load(own(v), e.weight, values(r)) + res.at(v, v < e.vmax);
  };
  auto guess = [&](ZoneRange r) {  // the root of a·v² + b·v = the allotment
    return res.root(0.5 * kappa * filter_.variance_s2(), delta * filter_.abs_moment_s(),
                    zone_allotment(share, e.weight, values(r)));
  };
  const double v = largest_speed_in_zones(e.vmax, share, e.s0, e.s1, tau, load, guess);
  e.err = own(v);
  e.reach0 = e.s0 - v * tau;
  e.reach1 = e.s1 + v * tau;
  if (v < e.vmax) e.cap = v;
  e.z0 = zone_back(e.s0, tau, e.cap);
  e.z1 = zone_fwd(e.s1, tau, e.cap);
}

double TolerancePlanner::corner_cost_s(const Element& e, double pause_s, double d, double share,
                                       const MismatchReserve& res, double v_ref, double& v) const {
  const double zt = std::max(filter_.zone_floor_s(), filter_.tau_s() - pause_s);
  ZoneMemo memo;
  auto load = [&](double s, ZoneRange r) {
    return zone_load(s * d * e.turn, e.turn, zone_values(memo, r, e, true)) + res.at(s, s < e.vmax);
  };
  auto guess = [&](ZoneRange r) {
    return res.root(0.0, d * e.turn, zone_allotment(share, e.turn, zone_values(memo, r, e, true)));
  };
  v = d > 0.0 ? largest_speed_in_zones(e.vmax, share, e.s0, e.s1, zt, load, guess) : e.vmax;
  // The slowing is shared by the elements in the zone (a run of short segments slows once);
  // the pause is e's alone.
  const double z0 = e.s0 - v * zt, z1 = e.s1 + v * zt;
  // Each side is at least one sample of travel at the fastest speed (emit_front's shortest
  // piece): ℓ at v instead of v_ref costs ℓ/v − ℓ/v_ref.
  const double side = std::max(v * zt, 1.01 * e.vmax * filter_.period_s());
  const ZoneRange zr = zone_range(z0, z1);
  const double slow = (v > 0.0 ? std::max(0.0, side / v - side / v_ref) : kInf) /
                      std::max(1.0, static_cast<double>(zr.last - zr.first));
  double cost = (pause_s - e.pause0) + 2.0 * slow;
  // An arc of several turns the zone touches takes the cap whole (it is not split): its
  // slowing counts too. Such an arc reaches into [z0, z1], so it is in the range.
  for (std::size_t i = zr.first; i < zr.last; ++i) {
    const Element& f = elems_[i];
    if (f.kind == ElementKind::Arc && !f.split && f.s1 > z0 && f.s0 < z1 && v < f.v100)
      cost += (f.s1 - f.s0) * (1.0 / v - 1.0 / f.v100);
  }
  return cost;
}

void TolerancePlanner::decide_corner(Element& e, double share, const MismatchReserve& res) {
  // The speed the interpolator would have here anyway: 100 % feed, or an earlier cap whose zone
  // already covers this corner (then slowing further costs only the difference).
  double v_ref = e.v100;
  for (const Element& f : elems_)
    if (f.decided && f.cap < kInf && f.z0 <= e.s0 && e.s0 <= f.z1) v_ref = std::min(v_ref, f.cap);
  // Corner: the pause P (at least what the program already dwells) and cap V with
  // V·D(P)·W <= share that cost the least time: the pause added plus the slowing in the zones,
  // (τ − P) of time either side at V instead of v_ref.
  // The pauses are tried in order, the first of the least cost kept. A pause whose cost cannot
  // beat one already known (`known`: the pause that was best at the corner decided before, tried
  // first) is passed over without its bisection: corner_cost_s is at least the pause plus the
  // slowing at the speed where the corner's own term V·D(P)·|Δu| alone fills the share (the
  // zone's load is never below that term, the slowing falls with the speed and is shared by no
  // more elements than that speed's zone holds).
  CornerMomentGrid& grid = grid_d();
  const double T = filter_.period_s();
  auto cost_at_least = [&](double p, double d) {
    double v = e.vmax;
    if (d > 0.0 && e.turn > 0.0) v = std::min(v, share / (d * e.turn) * (1.0 + 1e-9));
    if (!(v > 0.0)) return p - e.pause0;
    const double zt = std::max(filter_.zone_floor_s(), filter_.tau_s() - p);
    const double side = std::max(v * zt, 1.01 * e.vmax * T);
    const ZoneRange zr = zone_range(e.s0 - v * zt, e.s1 + v * zt);
    const double slow = std::max(0.0, side / v - side / v_ref) /
                        std::max(1.0, static_cast<double>(zr.last - zr.first));
    return (p - e.pause0) + 2.0 * slow;
  };
  double known = kInf, known_v = 0.0;
  const int known_j = last_corner_pause_j_;
  auto pause_at = [T](int j) { return 0.5 * static_cast<double>(2 * j) * T; };  // grid pause j
  const double known_p = pause_at(known_j);
  if (known_j >= 0 && known_j < grid.size() && known_p > e.pause0)
    known = corner_cost_s(e, known_p, grid.at(known_j), share, res, v_ref, known_v);
  double best_cost = kInf, best_p = e.pause0, best_v = 0.0, best_d = 0.0;
  int best_j = -1;
  auto consider = [&](double p, double d, int j) {
    if (p - e.pause0 >= best_cost) return false;  // pauses only get longer from here
    double v = 0.0, cost = kInf;
    if (j >= 0 && j == known_j && known < kInf) {
      cost = known;
      v = known_v;
    } else {
      if (cost_at_least(p, d) > std::min(best_cost, known) + 1e-9) return true;
      cost = corner_cost_s(e, p, d, share, res, v_ref, v);
    }
    if (cost < best_cost - 1e-12) {
      best_cost = cost;
      best_p = p;
      best_v = v;
      best_d = d;
      best_j = j;
    }
    return true;
  };
  consider(e.pause0, corner_moment(e.pause0), -1);
  for (int j = 0; j < grid.size(); ++j) {
    const double p = pause_at(j);
    if (p > e.pause0 && !consider(p, grid.at(j), j)) break;
  }
  if (best_j >= 0) last_corner_pause_j_ = best_j;
  settle_corner(e, best_p, best_v, best_d, best_cost);
  // Its full stop (the drain pause, D = 0: no cap, err 0), priced for the arc after it to weigh
  // (decide_arc_weighing).
  e.stop_cost_s = kInf;
  const double p_stop = drain_pause_s();
  if (p_stop > e.pause0 && best_d > 0.0) {
    double v_stop = 0.0;
    e.stop_cost_s = corner_cost_s(e, p_stop, 0.0, share, res, v_ref, v_stop);
  }
}

void TolerancePlanner::settle_corner(Element& e, double pause, double v_cap, double d,
                                     double cost) const {
  e.pause = pause;
  e.cost_s = cost;
  e.stopped = !(d > 0.0);
  e.cap = v_cap < e.vmax ? v_cap : kInf;
  const double zt = std::max(filter_.zone_floor_s(), filter_.tau_s() - pause);
  const double v = std::min(v_cap, e.vmax);
  e.err = v * d * e.turn;  // V·D(P)·|Δu|
  e.reach0 = e.s0 - v * zt;
  e.reach1 = e.s1 + v * zt;
  e.z0 = zone_back(e.s0, zt, e.cap);
  e.z1 = zone_fwd(e.s1, zt, e.cap);
}

double TolerancePlanner::slowing_s(const Element& arc) const {
  // Its zone (the arc and the stretches beside it) at its cap instead of each block's speed at
  // 100 %: a slow arc's zone reaching into a rapid costs the rapid's time, not the arc's; its
  // slower ends, their stretches at their caps.
  const double v = std::min(arc.cap, arc.vmax);
  if (!(v > 0.0)) return 0.0;
  double cost = stretch_slowing_s(arc.z0, arc.z1, v);
  if (arc.slower_ends())
    for (const Element::EndCap& c : arc.ends)
      if (c.cap < v)
        cost += stretch_slowing_s(c.lo, c.hi, c.cap) - stretch_slowing_s(c.lo, c.hi, v);
  return cost;
}

double TolerancePlanner::stretch_slowing_s(double z0, double z1, double v) const {
  // The blocks in path order: from the first ending past z0 to the last starting before z1.
  auto b = std::lower_bound(window_.begin(), window_.end(), z0,
                            [](const Block& blk, double z) { return blk.s1 <= z; });
  double cost = 0.0;
  for (; b != window_.end() && b->s0 < z1; ++b) {
    const double len = std::min(b->s1, z1) - std::max(b->s0, z0);
    if (len > 0.0 && v < b->v100) cost += len / v - len / b->v100;
  }
  return cost;
}

void TolerancePlanner::set_weight(Element& f, double w) {
  // f's weight, and the prefix sums of the elements after it.
  const double delta = w - f.weight;
  if (delta == 0.0) return;
  f.weight = w;
  bool after = false;
  for (Element& g : elems_) {
    if (after) g.cum += delta;
    after = after || &g == &f;
  }
  weight_total_ += delta;
}

void TolerancePlanner::decide_arc_weighing(Element& a, double share, const MismatchReserve& res) {
  // The corners at the arc's two ends share its zone: the one before it (decided just now, its
  // err counted) and the one after it (undecided, counted by its weight, then decided within
  // what the arc left; at its end, or past a tangent line within τ of it at the fastest
  // speeds, where a stop still parts the arc from the tolerances beyond: tolerance_near). A full
  // stop at either (the drain pause: err 0, no weight) leaves the arc more of the share. The four
  // plans are weighed by their costs in the decisions' own terms (the corners' cost_s or
  // stop_cost_s, the arc's slowing_s, the corner after decided on a copy), a plan whose stops alone
  // cost more than the best known not tried; the cheapest is kept.
  const Element before = a;
  decide_arc_beside_claims(a, share, res);
  if (!(a.cap < kInf)) return;  // nothing to gain
  const double p_stop = drain_pause_s();
  if (!(p_stop >= 0.0)) return;
  std::size_t ia = elems_.size();
  for (std::size_t k = decided_prefix_; k < elems_.size(); ++k)
    if (&elems_[k] == &a) {
      ia = k;
      break;
    }
  if (ia == elems_.size()) return;
  auto plain_corner = [&](const Element& f) {
    return f.kind == ElementKind::Corner && f.untol_for == 0 &&
           f.claim_state != Element::Claim::Claimant;
  };
  // The corner before: decided, nothing after it but the arc since, and its block (where its
  // pause goes) not yet handed on.
  Element* cs = nullptr;
  if (ia > 0 && plain_corner(elems_[ia - 1]) && elems_[ia - 1].decided &&
      elems_[ia - 1].s1 >= a.s0 - 1e-9 && decided_prefix_ == ia && decided_count_ == ia &&
      elems_[ia - 1].stop_cost_s < kInf && elems_[ia - 1].seq >= window_.front().seq)
    cs = &elems_[ia - 1];
  Element* ce = nullptr;
  if (ia + 1 < elems_.size() && plain_corner(elems_[ia + 1]) && !elems_[ia + 1].decided &&
      elems_[ia + 1].turn > kClaimTurn && elems_[ia + 1].t0 < a.t1 + filter_.tau_s() &&
      p_stop > elems_[ia + 1].pause0)
    ce = &elems_[ia + 1];
  if (cs == nullptr && ce == nullptr) return;
  const Element start = cs != nullptr ? *cs : Element{}, end = ce != nullptr ? *ce : Element{};
  Element start_stop = start, end_stop = end;
  if (cs != nullptr) {
    settle_corner(start_stop, p_stop, start.vmax, 0.0, start.stop_cost_s);
    start_stop.weight = 0.0;
  }
  if (ce != nullptr) {
    end_stop.decided = true;
    end_stop.share = share_of(tolerance_near(end));
    end_stop.claim_state = Element::Claim::Share;
    settle_corner(end_stop, p_stop, end.vmax, 0.0, p_stop - end.pause0);
    end_stop.weight = 0.0;
  }
  const double start_cost = cs != nullptr ? start.cost_s : 0.0;
  // An element's saved state put back, its weight with the prefix sums after it, and its own
  // prefix sum as it is now (the weights before it may have changed since it was saved).
  auto restore = [&](Element& f, const Element& saved) {
    set_weight(f, saved.weight);
    const double cum = f.cum;
    f = saved;
    f.cum = cum;
  };
  // Puts a plan's corners in place (weights and prefix sums too), the arc undecided.
  auto place = [&](bool stop_start, bool stop_end) {
    if (cs != nullptr) restore(*cs, stop_start ? start_stop : start);
    if (ce != nullptr) restore(*ce, stop_end ? end_stop : end);
    restore(a, before);
  };
  using Plan = std::pair<bool, bool>;  // stops at the start, at the end
  // The arc decided in a plan: a stop parts it from the tolerances beyond it (tolerance_near),
  // and its zone ends there (decide_arc).
  const double tol = tolerance_near(a);
  auto decide_parted = [&] {
    const double t = tolerance_near(a);
    if (t == tol) {
      decide_arc_beside_claims(a, share, res);
    } else {
      a.share = share_of(t);
      decide_arc_beside_claims(a, a.share, mismatch_reserve(a, t));
    }
  };
  // The corner after decided on a copy beside the arc as it is: its cost.
  auto end_cost = [&] {
    const Element decided_arc = a;
    const std::size_t prefix = decided_prefix_;
    extend_decided_prefix();
    decide(*ce);
    const double cost = ce->cost_s;
    restore(*ce, end);
    decided_prefix_ = prefix;
    restore(a, decided_arc);
    return cost;
  };
  // The plans' costs. The corner after costs at most its own stop (one of the pauses it tries):
  // a plan where it does not stop is known within [c, c + that] until it is decided on a copy
  // (end_cost), which is done only where that could change the choice; a plan whose stops alone
  // cost more than the best known is not tried. Among equal costs the plan as planned wins.
  ++weigh_depth_;
  struct Tried {
    Plan plan;
    double cost;  // exact, or the lower end when `open`
    bool open;    // the corner after does not stop and is not decided yet
    Element arc;  // the arc's decision in the plan
  };
  std::array<Tried, 4> tried{};
  std::size_t n = 0;
  const double end_at_most = ce != nullptr ? end_stop.cost_s : 0.0;
  auto floor_of = [&](Plan p) {
    return (p.first ? start_stop.cost_s : start_cost) + (p.second ? end_stop.cost_s : 0.0);
  };
  auto best_closed = [&] {
    double best = kInf;
    for (std::size_t i = 0; i < n; ++i)
      if (!tried[i].open) best = std::min(best, tried[i].cost);
    return best;
  };
  tried[n++] = {Plan{false, false}, start_cost + slowing_s(a), ce != nullptr, a};
  const double upper = tried[0].cost + end_at_most;  // the plan as planned costs at most this
  // Every stop there can be first: the arc's share is then the largest, its slowing the least
  // of any plan's, which bounds the others' from below.
  // With one corner there is only that plan.
  const Plan all{cs != nullptr, ce != nullptr};
  const std::array<Plan, 3> plans{all, Plan{false, true}, Plan{true, false}};
  const std::size_t count = cs != nullptr && ce != nullptr ? 3 : 1;
  double least_slowing = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const Plan& p = plans[i];
    // Its stops and the least slowing cost more than the best known: not tried.
    if (!(floor_of(p) + least_slowing < std::min(upper, best_closed()))) continue;
    place(p.first, p.second);
    decide_parted();
    if (p == all) least_slowing = slowing_s(a);
    tried[n++] = {p, floor_of(p) + slowing_s(a), ce != nullptr && !p.second, a};
  }
  if (n == 1) {  // nothing else could be cheaper: the arc stays as decided
    --weigh_depth_;
    return;
  }
  // The open plans, decided where they could still be the cheapest.
  for (std::size_t i = 0; i < n; ++i) {
    Tried& t = tried[i];
    if (!t.open || !(t.cost < best_closed() + 1e-9)) continue;
    place(t.plan.first, t.plan.second);
    restore(a, t.arc);
    t.cost += end_cost();
    t.open = false;
  }
  // The cheapest closed plan, the plan as planned first among equals.
  const double best = best_closed();
  std::size_t pick = 0;
  while (tried[pick].open || !(tried[pick].cost < best + 1e-9)) ++pick;
  --weigh_depth_;
  place(tried[pick].plan.first, tried[pick].plan.second);
  restore(a, tried[pick].arc);                    // its decision beside them
  if (tried[pick].plan.second) ++decided_count_;  // the corner after, decided out of order
}

double TolerancePlanner::drain_pause_s() {
  // The first pause of the grid whose corner moment is 0: the window holds the vertex only.
  if (drain_j_ == -2) {
    CornerMomentGrid& grid = grid_d();
    drain_j_ = -1;
    for (int j = 0; j < grid.size() && drain_j_ < 0; ++j)
      if (!(grid.at(j) > 0.0)) drain_j_ = j;
  }
  return drain_j_ < 0 ? -1.0 : static_cast<double>(drain_j_) * filter_.period_s();
}

void TolerancePlanner::emit_front() {
  const double tau = filter_.tau_s();
  if (!ended_ && window_.size() >= cfg_.capacity && !window_.back().stop_after) {
    Block& last = window_.back();
    const bool exact_path = last.m.path_mode == PathMode::ExactPath && !last.tangent_exit;
    mark_stop(last);
    last.forced_stop = !exact_path;  // an exact-path end stops as it is
  }
  Block& b = window_.front();
  decide_reachable(emit_horizon_t(b));
  const Element* own = arc_of(b);  // b's arc element (its own or its chain's), if an arc
  // v_p when pre-compensated (a G61 arc: at its fastest speed, exact_path_comp_speed)
  const double comp_v = own != nullptr ? own->comp_speed : exact_path_comp_speed(b);
  const Element* chain = comp_v > 0.0 && own != nullptr && own->seq_last > own->seq ? own : nullptr;
  if (chain == nullptr) {
    cut_pieces(b.s0, b.s1, b.cap_all, b.m.kind == MotionKind::Arc && !splits(b.m), comp_v, own);
    merge_short_pieces(b);
    brake_comp_pieces(comp_v);
  } else if (b.seq == chain->seq) {  // the chain's pieces, cut once (its blocks are alike)
    double cap_all = kInf;
    const Block* last = &b;
    for (const Block& c : window_)
      if (c.seq <= chain->seq_last) {
        cap_all = std::min(cap_all, c.cap_all);
        last = &c;
      }
    cut_pieces(chain->s0, chain->s1, cap_all, false, comp_v, chain);
    merge_short_pieces(b);
    brake_comp_pieces(comp_v);
    chain_pieces_ = pieces_;
    // Every block of the chain takes the rows its end takes (they act near that end only),
    // judged at its last piece's v_p.
    chain_stops_ = comp_stops_after(*last, chain_pieces_.back().plan_or(comp_v));
  }
  emit_pieces(b, comp_v, chain);
  const std::size_t last_piece = ready_.size() - 1;
  for (const Element& e : elems_)
    if (e.kind != ElementKind::Arc && e.seq == b.seq && e.pause > e.pause0 + 1e-12)
      make_ready(Dwell{b.m.line, e.pause - e.pause0});
  if (Motion& arc = std::get<Motion>(ready_[last_piece].canon);
      arc.comp_speed_mm_s > 0.0 && chain == nullptr)
    arc.comp_stops_at_end = comp_stops_after(b, arc.comp_speed_mm_s);
  if (b.forced_stop) make_ready(Dwell{b.m.line, tau});
  for (Canon& c : b.after) make_ready(std::move(c));
  emitted_t1_ = b.t1;
  if (b.m.path_tolerance_mm > 0.0) toleranced_t1_ = b.t1;
  window_.pop_front();
  // Elements that can no longer reach a block still to come, nor be counted by one.
  const double keep_from = window_.empty() ? kInf : window_.front().t0 - 2.0 * tau;
  while (!elems_.empty() && elems_.front().decided && elems_.front().t1 < keep_from) {
    elems_.pop_front();
    if (claim_cursor_ > 0) --claim_cursor_;
    --decided_count_;
    if (decided_prefix_ > 0) --decided_prefix_;
  }
}

double TolerancePlanner::exact_path_comp_speed(const Block& b) const {
  // A G61 arc keeps its feed (exact path rounds no corner, and it does not slow an arc).
  // Commanded pre-compensated at its fastest speed, its steady part lies on the programmed arc
  // instead of r·(1 − A(ωT)) inside it, and its ends leave what the transitions leave: not
  // planned against anything, as G61 has no P. Not where A(ωT) falls below kMinGain at that
  // speed, nor within τ of a block with a tolerance (whose plan counts this arc as the filter
  // shrinks it).
  if (!cfg_.precompensate_g61_arcs || !precomp_ || b.m.kind != MotionKind::Arc ||
      b.m.path_mode != PathMode::ExactPath || b.m.path_tolerance_mm > 0.0 ||
      b.t0 < toleranced_t1_ + filter_.tau_s())
    return 0.0;
  for (const Block& c : window_) {  // in path order: those starting within τ after b
    if (!(c.t0 < b.t1 + filter_.tau_s())) break;
    if (c.m.path_tolerance_mm > 0.0) return 0.0;
  }
  const Element e = arc_element(b);
  if (!(e.radius > 0.0) || e.spiral > 0.0 || !(e.sweep > 0.0)) return 0.0;
  return b.vmax <= precomp_->speed_limit_mm_s(e.sweep, b.s1 - b.s0) ? b.vmax : 0.0;
}

bool TolerancePlanner::comp_stops_after(const Block& b, double comp_v) const {
  // Its command stops on its end point (a pause at the corner after it, or stops_after). So
  // does, for its end rows, one followed by a block that crawls in comparison (at most
  // kCrawlRatio of v_p at its fastest): its check simulates the end moving on at v_p and
  // stopping, and a step down to a few % of v_p is a stop far more than it is moving on.
  for (const Element& e : elems_)
    if (e.kind != ElementKind::Arc && e.seq == b.seq && e.pause > e.pause0 + 1e-12) return true;
  const std::size_t i = static_cast<std::size_t>(b.seq - window_.front().seq);  // b's slot
  const Block* next = i + 1 < window_.size() ? &window_[i + 1] : nullptr;
  if (next != nullptr && next->vmax < kCrawlRatio * comp_v) return true;
  return stops_after(b) || (ended_ && next == nullptr);
}

bool TolerancePlanner::stops_after(const Block& b) const {
  // What the interpolator waits on at the block's end before it moves on (its step_n): an exact
  // stop, a dwell, an input wait with a timeout, the end of the program or of the stream.
  if (b.forced_stop || b.dwell_after_s > 0.0 || (ended_ && window_.size() == 1)) return true;
  if (b.m.path_mode != PathMode::Continuous && !b.tangent_exit) return true;
  for (const Canon& c : b.after)
    if (const auto* e = std::get_if<Event>(&c);
        e != nullptr &&
        (e->kind == EventKind::End ||
         (e->kind == EventKind::WaitInput && e->mode >= 1 && e->mode <= 3 && e->value > 0.0)))
      return true;
  return false;
}

void TolerancePlanner::decide_reachable(double t1_s) {
  const double tau = filter_.tau_s();
  if (run_.open) {  // a chunk some decision can reach is closed first, so that it is counted
    double horizon = t1_s + 2.0 * tau;
    for (const Element& e : elems_)
      if (!e.decided && e.t0 < t1_s + tau) horizon = std::max(horizon, e.t1 + tau);
    if (run_.chunk.t0 < horizon) close_run_chunk();
  }
  for (std::size_t i = 0; i < elems_.size(); ++i) {
    Element& e = elems_[i];
    if (e.decided || !(e.t0 < t1_s + tau)) continue;
    if (e.untol_for != 0) {
      decide_untoleranced_group(i);
      continue;
    }
    decide(e);
    ++decided_count_;
    extend_decided_prefix();
  }
}

void TolerancePlanner::decide_untoleranced_group(std::size_t i) {
  // The group: the elements plan_untoleranced pushed for one block, in a row. They matter to
  // that block's samples only while the command can still reach it within τ of passing them.
  // Decided from the one nearest the block back: an element wholly before the zone of a capped
  // element already decided there is let go (no cap, no pause, err 0): the command crosses that
  // zone at the cap, τ − P of time, and pauses P (or stops where the zone ends at a stop), so
  // it reaches the block τ or more after it, when the filter holds nothing of it.
  const std::uint64_t group = elems_[i].untol_for;
  std::size_t last = i;
  while (last + 1 < elems_.size() && elems_[last + 1].untol_for == group) ++last;
  const double front_s0 = window_.front().s0;
  auto let_go = [&](Element& g, double pause) {
    g.decided = true;
    g.cap = kInf;
    g.err = 0.0;
    g.share = share_of(g.tol_mm);
    g.pause = pause;
    g.stopped = false;
    g.cost_s = pause - g.pause0;
    g.reach0 = g.s0;
    g.reach1 = g.s1;
    g.z0 = g.z1 = g.s0;
  };
  // As planned: the sum of the decisions' costs (corner_cost_s).
  auto plan = [&] {
    double shield = -kInf;  // elements ending before this are let go
    double cost = 0.0;
    for (std::size_t k = last + 1; k-- > i;) {
      Element& g = elems_[k];
      if (g.decided) continue;
      if (g.s1 < shield - 1e-9) {
        let_go(g, g.pause0);
      } else {
        decide(g);
        cost += g.cost_s;
      }
      ++decided_count_;
      // A zone cut short by the window's front does not cover τ − P of time.
      if (g.cap < kInf && g.z0 > front_s0 + 1e-9) shield = std::max(shield, g.z0);
    }
    return cost;
  };
  // Or a full stop at the corner nearest the block: the filter drains there (the pause of the
  // grid whose moment is 0), and every element before it is let go. Weighed when the group is
  // corners only (their costs are in the same terms: a pause added costs its time).
  Element& near = elems_[last];
  bool corners = near.kind == ElementKind::Corner;
  for (std::size_t k = i; k <= last && corners; ++k)
    corners = !elems_[k].decided && elems_[k].kind == ElementKind::Corner;
  const double stop_pause = corners ? drain_pause_s() : -1.0;
  if (!(stop_pause > near.pause0)) {  // no stop to weigh, or one already there
    plan();
    extend_decided_prefix();
    return;
  }
  assign_claims(near.t1 + filter_.tau_s());  // what decide(near) assigns first, before the copy
  saved_group_.assign(elems_.begin() + static_cast<std::ptrdiff_t>(i),
                      elems_.begin() + static_cast<std::ptrdiff_t>(last + 1));
  const int saved_j = last_corner_pause_j_;
  const double planned = plan();
  if (stop_pause - near.pause0 < planned - 1e-9) {
    std::copy(saved_group_.begin(), saved_group_.end(),
              elems_.begin() + static_cast<std::ptrdiff_t>(i));
    last_corner_pause_j_ = saved_j;
    for (std::size_t k = i; k <= last; ++k) let_go(elems_[k], elems_[k].pause0);
    let_go(near, stop_pause);
    near.stopped = true;
  }
  extend_decided_prefix();
}

void TolerancePlanner::cut_pieces(double s0, double s1, double cap_all, bool whole, double comp_v,
                                  const Element* own) {
  // Pieces of the block between zone boundaries, each with the smallest cap over it.
  // An arc of several turns is not split: it takes the smallest cap of the zones touching it.
  // A pre-compensated arc is cut, but not within kCompEndSamples samples of travel at v_p of its
  // ends (its end rows, radial blend and speed hold are the whole arc's, as its plan judged
  // them): a cut nearer an end moves away from it, and each piece takes the smallest cap of
  // the zones overlapping it (the slower piece grows).
  double lo = s0, hi = s1;
  if (comp_v > 0.0) {
    const double end = kCompEndSamples * filter_.period_s() * comp_v;
    lo = s0 + end;
    hi = s1 - end;
    if (!(hi > lo)) whole = true;
  }
  std::vector<double>& cuts = cuts_;
  cuts.assign({s0, s1});
  // Each decided element's capped stretches: its zone, and an arc's slower ends'.
  auto each_capped = [&](auto fn) {
    for (const Element& e : elems_) {
      if (!e.decided) continue;
      if (e.cap < kInf) fn(e.z0, e.z1, e.cap);
      if (e.slower_ends())
        for (const Element::EndCap& c : e.ends)
          if (c.cap < kInf) fn(c.lo, c.hi, c.cap);
    }
  };
  if (!whole)
    each_capped([&](double z0, double z1, double) {
      for (double z : {z0, z1})
        if (z > s0 && z < s1) cuts.push_back(std::clamp(z, lo, hi));
    });
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  std::vector<Piece>& pieces = pieces_;
  pieces.clear();
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double a = cuts[i], c = cuts[i + 1];
    if (c - a < 1e-9 && !pieces.empty()) {  // a sliver: joins the piece before
      pieces.back().c = c;
      continue;
    }
    double cap = cap_all;
    each_capped([&](double z0, double z1, double zcap) {
      const bool covers =
          whole || comp_v > 0.0 ? (z0 < c && z1 > a) : (z0 <= 0.5 * (a + c) && 0.5 * (a + c) <= z1);
      if (covers) cap = std::min(cap, zcap);
    });
    if (!pieces.empty() && pieces.back().cap == cap)
      pieces.back().c = c;
    else
      pieces.push_back({a, c, cap});
  }
  // The chain's own pieces over its slower ends are planned at those ends' caps.
  if (own != nullptr && own->slower_ends())
    for (Piece& q : pieces)
      for (const Element::EndCap& e : own->ends)
        if (e.cap < kInf && e.lo < q.c && e.hi > q.a) q.plan = std::min(q.plan_or(comp_v), e.cap);
}

void TolerancePlanner::merge_short_pieces(const Block& b) {
  // With a servo mismatch reserve (speed_error_s, planned for the table): no piece shorter than
  // one sample of travel at the block's fastest speed. A merged piece takes the smaller cap
  // (never faster than planned). The rule was first made for the contour measurement, which
  // since sees every block a sample starts; without it the plans without a reserve (the Acc/Dec
  // output's) hold P on every sample of their sweeps and run faster, while one encoder plan of
  // the default machine's 1,000 overshot a corner after a step down from 130 to 0.5 mm/s in its
  // short zone (docs/tolerance.md, "Short pieces"), so every plan with a reserve keeps it.
  if (!(cfg_.speed_error_s > 0.0)) return;
  std::vector<Piece>& pieces = pieces_;
  const double min_piece = 1.01 * b.vmax * filter_.period_s();
  for (std::size_t i = 0; pieces.size() > 1 && i < pieces.size();) {
    if (pieces[i].c - pieces[i].a >= min_piece) {
      ++i;
      continue;
    }
    const std::size_t j = i + 1 < pieces.size() ? i + 1 : i - 1;  // the neighbour it joins
    const std::size_t lo = std::min(i, j), hi = std::max(i, j);
    // A slower short piece takes from its neighbour only what it lacks, when the neighbour
    // keeps a sample's travel: merging a short capped zone into a whole uncapped leg would
    // slow the leg (the encoder chain's corner zones are a fraction of a millimetre).
    const double need = min_piece - (pieces[i].c - pieces[i].a);
    if (pieces[i].cap < pieces[j].cap && pieces[j].c - pieces[j].a - need >= min_piece) {
      if (j > i)
        pieces[i].c = pieces[j].a = pieces[i].c + need;
      else
        pieces[i].a = pieces[j].c = pieces[i].a - need;
      ++i;
      continue;
    }
    pieces[lo] = {pieces[lo].a, pieces[hi].c, std::min(pieces[lo].cap, pieces[hi].cap)};
    pieces.erase(pieces.begin() + static_cast<std::ptrdiff_t>(hi));
    i = lo;
  }
}

void TolerancePlanner::brake_comp_pieces(double comp_v) {
  // The pieces of a pre-compensated arc change speed by the arc's ramp (v_p/(N + 1) a sample),
  // which its plan judged; a piece brakes to the next one's cap before its end
  // (Motion::comp_exit_speed_mm_s). A piece too short for that takes the next one's cap.
  std::vector<Piece>& pieces = pieces_;
  if (!(comp_v > 0.0) || pieces.size() < 2) return;
  for (std::size_t i = pieces.size() - 1; i-- > 0;) {
    const double plan = pieces[i].plan_or(comp_v);
    const double from = std::min(pieces[i].cap, plan),
                 to = std::min(pieces[i + 1].cap, pieces[i + 1].plan_or(comp_v));
    if (!(to < from)) continue;
    if (pieces[i].c - pieces[i].a < braking_length_mm(from, to, plan))
      pieces[i].cap = pieces[i + 1].cap;
  }
}

double TolerancePlanner::braking_length_mm(double from, double to, double comp_v) const {
  // The ramp's samples from `from` down to `to`, one more at `from` (the sample it starts in).
  const double step = precomp_->rule().speed_step_mm_s(comp_v), T = filter_.period_s();
  const double m = std::ceil((from - to) / step);
  return T * ((m + 1.0) * to + step * (m + 1.0) * (m + 2.0) / 2.0);
}

void TolerancePlanner::emit_pieces(const Block& b, double comp_v, const Element* chain) {
  const double L = b.s1 - b.s0;
  // A chain's block: its part of the chain's pieces, and where each of those ends and the
  // speed the next one needs (the chain's ramp brakes to it before that end).
  if (chain != nullptr) {
    block_pieces_.clear();
    for (std::size_t k = 0; k < chain_pieces_.size(); ++k) {
      const Piece& q = chain_pieces_[k];
      const double a = std::max(q.a, b.s0), c = std::min(q.c, b.s1);
      if (!(c - a > 1e-9) && !(q.a <= b.s0 && b.s1 <= q.c)) continue;
      const double next =
          k + 1 < chain_pieces_.size()
              ? std::min(chain_pieces_[k + 1].cap, chain_pieces_[k + 1].plan_or(comp_v))
              : comp_v;
      const double speed = std::min(q.cap, q.plan_or(comp_v));
      block_pieces_.push_back({a, c, q.cap, q.c, next < speed ? next : 0.0, q.plan});
    }
  }
  const std::vector<Piece>& pieces = chain != nullptr ? block_pieces_ : pieces_;
  const double arc_s0 = chain != nullptr ? chain->s0 : b.s0;
  const double arc_len = chain != nullptr ? chain->s1 - chain->s0 : L;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    Ready& r = ready_.push_back_slot();  // the piece is written in its slot
    r.canon = b.m;
    Motion& p = std::get<Motion>(r.canon);
    r.has_geometry = pieces.size() == 1;  // one piece: the block whole, b's geometry
    if (r.has_geometry) r.g = b.g;
    const Piece& q = pieces[i];
    if (pieces.size() > 1) {
      p.start_mm = i == 0 ? b.m.start_mm : b.g.at_fraction((q.a - b.s0) / L);
      p.end_mm = i + 1 == pieces.size() ? b.m.end_mm : b.g.at_fraction((q.c - b.s0) / L);
      if (b.m.inverse_time_s > 0.0) p.inverse_time_s = b.m.inverse_time_s * (q.c - q.a) / L;
    }
    if (q.cap < b.vmax * (1.0 - 1e-12)) p.speed_cap_mm_s = q.cap;
    p.comp_speed_mm_s = q.plan_or(comp_v);
    if (chain != nullptr) {  // a piece of the chain's arc
      p.comp_arc_from_mm = q.a - arc_s0;
      p.comp_arc_length_mm = arc_len;
      // It brakes to the next piece's speed by its own end where the chain's piece ends in it,
      // or where what is left of that piece past this block is too short to brake in.
      const double plan = q.plan_or(comp_v);
      if (q.exit_speed > 0.0 &&
          (q.exit_at <= b.s1 + 1e-9 ||
           q.exit_at - b.s1 < braking_length_mm(std::min(q.cap, plan), q.exit_speed, plan)))
        p.comp_exit_speed_mm_s = q.exit_speed;
      p.comp_stops_at_end = chain_stops_;
    } else if (comp_v > 0.0 && pieces.size() > 1) {  // a piece of the arc (cut_pieces)
      p.comp_arc_from_mm = q.a - b.s0;
      p.comp_arc_length_mm = L;
      if (i + 1 < pieces.size() && std::min(pieces[i + 1].cap, comp_v) < std::min(q.cap, comp_v))
        p.comp_exit_speed_mm_s = std::min(pieces[i + 1].cap, comp_v);
    }
    if (i + 1 < pieces.size()) {  // the contour measurement measures to the block's end
      p.rest_of_block = true;
      p.block_end_mm = b.m.end_mm;
    }
    // Only the block's end stops (G61.1, G9, G61 at a join that is not tangent).
    if (i + 1 < pieces.size() || b.tangent_exit) p.path_mode = PathMode::Continuous;
  }
}

bool TolerancePlanner::next(Canon& out) {
  while (ready_.empty()) {
    if (window_.empty()) {
      if (ended_) return false;
      pull();
      continue;
    }
    if (!lookahead_enough()) {
      pull();
      continue;
    }
    emit_front();
  }
  Ready& r = ready_.front();
  out = std::move(r.canon);
  out_geometry_ = r.has_geometry ? &r.g : nullptr;  // the slot stays until the next push
  ready_.pop_front();
  return true;
}

void TolerancePlanner::make_ready(Canon&& c, const BlockGeometry* g) {
  Ready& r = ready_.push_back_slot();
  r.canon = std::move(c);
  r.has_geometry = g != nullptr;
  if (g != nullptr) r.g = *g;
}

}  // namespace gm
