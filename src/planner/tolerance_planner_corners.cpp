// TolerancePlanner's corners and runs: a pause or a cap each, the cheaper, within its share.
#include "planner/tolerance_planner.hpp"

#include "common/units.hpp"
#include "planner/tolerance_planner_zone_speed.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>

namespace gm {

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
  // (decide_weighing_stops).
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

std::size_t TolerancePlanner::index_past_prefix(const Element& e) const {
  for (std::size_t k = decided_prefix_; k < elems_.size(); ++k)
    if (&elems_[k] == &e) return k;
  return elems_.size();
}

void TolerancePlanner::restore(Element& f, const Element& saved) {
  set_weight(f, saved.weight);
  const double cum = f.cum;
  f = saved;
  f.cum = cum;
}

void TolerancePlanner::decide_corner_weighing(Element& e, double tol, double share,
                                              const MismatchReserve& res) {
  // A smaller tolerance within τ past e lowers e's share (tolerance_near), and so its cap, as
  // it does every element's it reaches; a full stop at the corner after e (the drain pause:
  // err 0, no weight) parts e from it. The two plans are weighed by their costs in the
  // decisions' own terms (decide_weighing_stops'): e's cost_s, plus the corner after decided
  // on a copy beside e as planned, or that corner's stop. The plan as planned wins among
  // equals.
  const Element undecided = e;
  const int hint = last_corner_pause_j_;
  decide_corner(e, share, res);
  part_zone(e);
  const double planned_cost = e.cost_s;
  if (!(tol < e.tol_mm)) return;
  const double p_stop = drain_pause_s();
  if (!(p_stop >= 0.0)) return;
  // The corner after: next in path order, not decided, not claiming, reached within τ, and not
  // stopping already.
  const std::size_t ie = index_past_prefix(e);
  if (ie + 1 >= elems_.size()) return;
  Element& c = elems_[ie + 1];
  if (c.kind != ElementKind::Corner || c.untol_for != 0 ||
      c.claim_state == Element::Claim::Claimant || c.decided || !(c.t0 < e.t1 + filter_.tau_s()) ||
      !(p_stop > c.pause0))
    return;
  const Element planned = e, corner = c;
  const int planned_hint = last_corner_pause_j_;
  const Element corner_stop = stopped_corner(corner, p_stop, true);
  restore(c, corner_stop);
  const double parted = tolerance_near(e);
  if (!(parted > tol)) {  // the smaller tolerance is not (only) beyond that corner
    restore(c, corner);
    return;
  }
  ++weigh_depth_;
  // The stop's plan: e decided within the tolerance the stop leaves it.
  restore(e, undecided);
  last_corner_pause_j_ = hint;
  e.share = share_of(parted);
  decide_corner(e, e.share, mismatch_reserve(e, parted));
  part_zone(e);
  const double stop_cost = e.cost_s + corner_stop.cost_s;
  // The plan as planned costs at least e's cost there (the corner after costs nothing or more) and
  // at most that plus the corner's stop (one of the pauses it tries).
  bool stop = stop_cost < planned_cost - 1e-9;
  if (!stop && stop_cost < planned_cost + corner_stop.cost_s - 1e-9) {
    const Element stopped_plan = e;
    const int stopped_hint = last_corner_pause_j_;
    restore(e, planned);
    restore(c, corner);
    last_corner_pause_j_ = planned_hint;
    const double as_planned = planned_cost + cost_decided_aside(c, e);
    restore(c, corner_stop);
    restore(e, stopped_plan);
    last_corner_pause_j_ = stopped_hint;
    stop = stop_cost < as_planned - 1e-9;
  }
  --weigh_depth_;
  if (stop) {
    ++decided_count_;  // the corner after, decided out of order
    return;
  }
  restore(c, corner);
  restore(e, planned);
  last_corner_pause_j_ = planned_hint;
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

}  // namespace gm
