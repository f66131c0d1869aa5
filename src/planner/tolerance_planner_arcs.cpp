// TolerancePlanner's arcs: curvature bound or pre-compensated cap, slower ends; the stops beside
// an arc or a run, weighed.
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

namespace {

/// The largest speed in [lo, hi] with ok (monotone: true below a speed, false above it; ok(lo)
/// taken as true): hi when ok(hi), else lo after ten halvings.
template <class Ok>
double largest_fitting(double lo, double hi, Ok ok) {
  if (ok(hi)) return hi;
  for (int it = 0; it < 10; ++it) {
    const double mid = 0.5 * (lo + hi);
    (ok(mid) ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

void TolerancePlanner::decide_arc(Element& e, double share, const MismatchReserve& res) const {
  const double tau = filter_.tau_s();
  // κ·v²·σ²/2 <= (share − reserve)/W
  ZoneMemo memo;
  const double a = 0.5 * e.kappa * filter_.variance_s2();
  auto load = [&](double v, ZoneRange r) {
    return zone_load(a * v * v, 1.0, zone_values(memo, r, e, false, v * tau)) +
           res.at(v, v < e.vmax);
  };
  auto guess = [&](ZoneRange r) {
    const double left =
        std::max(0.0, zone_allotment(share, 1.0, zone_values(memo, r, e, false, memo.span)));
    return res.m_s > 0.0 ? res.root(a, 0.0, left) : std::sqrt(left / a);
  };
  double v = largest_speed_in_zones(e.vmax, share, e.s0, e.s1, tau, load, guess);
  e.comp_speed = 0.0;
  e.comp_private = false;
  e.err = a * v * v;
  e.ends = {};
  if (v < e.vmax && precomp_) {
    double err = 0.0;
    std::array<Element::EndCap, 2> ends{};
    bool private_arc = false;
    const double vc = precomp_arc_speed(e, share - res.ceiling_mm(), v, err, &ends, &private_arc);
    if (vc > v) {
      v = vc;
      e.comp_speed = vc;
      e.comp_private = private_arc;
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

TolerancePlanner::Privacy TolerancePlanner::arc_privacy(const Element& e, double v,
                                                        const ZoneMemo& z) const {
  Privacy p;
  if (window_.empty()) return p;
  // The arc's blocks (window_ holds blocks by sequence).
  const std::uint64_t first = window_.front().seq;
  if (e.seq < first || e.seq_last - first >= window_.size()) return p;
  const auto a0 = static_cast<std::size_t>(e.seq - first),
             a1 = static_cast<std::size_t>(e.seq_last - first);
  // A full stop at s (a corner where the filter drains, an exact stop), the block before it
  // `before` (null: not known here). Its element may lie outside the parted zone: a stop parts it.
  auto drained_at = [&](const Block* before, double s) {
    if (before != nullptr && before->stop_after) return true;
    for (std::size_t i = z.range.first; i < z.range.last; ++i) {
      const Element& f = elems_[i];
      if ((f.kind == ElementKind::Corner || f.kind == ElementKind::Stop) &&
          std::abs(f.s0 - s) <= 1e-9 &&
          (f.stopped || (f.decided && !(corner_moment(f.pause) > 0.0))))
        return true;
    }
    return false;
  };
  // A full stop at the arc's own start or end parts its windows from what lies beyond (the
  // check judges a start from rest, and a stop against the end point alone): reach ends there.
  const bool rest_before = drained_at(a0 > 0 ? &window_[a0 - 1] : nullptr, e.s0);
  const bool rest_after = drained_at(&window_[a1], e.s1);
  const double reach = v * filter_.tau_s();
  const double lo = rest_before ? e.s0 : e.s0 - reach, hi = rest_after ? e.s1 : e.s1 + reach;
  // No other arc, and no run of small turns, within reach (in its zone at v, parted at full
  // stops).
  for (std::size_t i = z.parted.first; i < z.parted.last; ++i) {
    const Element& f = elems_[i];
    if (f.s1 <= lo || f.s0 >= hi) continue;
    if (!same_element(f, e) && (f.kind == ElementKind::Arc || f.kind == ElementKind::Run)) return p;
  }
  // Every block within reach is still to be emitted (the lines before it then take the arc's
  // ramp for a change of the override: override_ramp_before), has a tolerance (an untoleranced
  // corner is no element), and is a line or the arc; those ahead are known (or the program
  // ends). Their joins turn by at most kPrivateTurn each, kPrivateTurns in all.
  if (window_.front().s0 > std::max(lo, 0.0) + 1e-9) return p;
  if (!ended_ && window_.back().s1 < hi) return p;
  std::size_t i0 = a0, i1 = a1;
  if (!rest_before)
    while (i0 > 0 && window_[i0 - 1].s1 > lo) --i0;
  if (!rest_after)
    while (i1 + 1 < window_.size() && window_[i1 + 1].s0 < hi) ++i1;
  const Block* prev = nullptr;
  for (std::size_t i = i0; i <= i1; ++i) {
    const Block& b = window_[i];
    const bool own = i >= a0 && i <= a1;  // a chain's blocks
    if (!(b.m.path_tolerance_mm > 0.0) || (!own && b.m.kind != MotionKind::Line)) return p;
    if (prev != nullptr) {
      const double turn = join_turn(*prev, b);
      if (turn > kMinTurn) {
        if (!(turn <= kPrivateTurn)) return p;
        p.turns += turn;
      }
    }
    prev = &b;
  }
  // A near circle at equal path length is its circle moved radially by δ(s), |δ'| <= Δr/L and
  // |δ| <= Δr/2: its path turns against the circle's by at most Δr/L + Δr/(2r).
  if (e.spiral > 0.0) {
    const double L = e.s1 - e.s0, r = e.radius - e.spiral;
    p.turns += e.spiral / L + e.spiral / (2.0 * r);
  }
  p.on = p.turns <= kPrivateTurns;
  return p;
}

double TolerancePlanner::precomp_arc_speed(const Element& e, double share, double floor,
                                           double& err, std::array<Element::EndCap, 2>* ends_out,
                                           bool* private_out) const {
  if (private_out != nullptr) *private_out = false;
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
  // A private arc (arc_privacy) is judged by the distance, its own table or runs, plus what
  // the turns beside it make of its drift (fits_private).
  auto fits_private = [&](double v, double allotment, double w, double turns) {
    using Judging = ArcPrecompCheck::Judging;
    double left = allotment;
    if (cfg_.speed_error_s > 0.0) {  // the command's offset by the distance's rows
      const ArcPrecompCheck::Judged judged(*precomp_, Judging::Private);
      left -= mismatch_at(v, false);
    }
    if (e.spiral > 0.0) {
      const ArcPrecompCheck::Judged judged(*precomp_, Judging::Private);
      left -= precomp_->spiral_mm(e.radius - e.spiral, e.radius, e.sweep, L, v, allotment);
    }
    if (turns > 0.0 && left > 0.0) {
      double drift;
      if (residual_drift_->covers(e.sweep, L, v)) {
        drift = residual_drift_->error_bound_mm(*precomp_, e.radius, e.sweep, L, v);
      } else {
        const ArcPrecompCheck::Judged judged(*precomp_, Judging::PrivateDrift);
        drift = precomp_->error_mm(e.radius, e.sweep, L, v);
      }
      left -= kDriftTurnFactor * turns * drift;
    }
    left *= w;
    if (!(left > 0.0)) return false;
    if (residual_private_->covers(e.sweep, L, v))
      return residual_private_->error_bound_mm(*precomp_, e.radius, e.sweep, L, v) * w <= left;
    const ArcPrecompCheck::Judged judged(*precomp_, Judging::Private);
    return precomp_->error_within(e.radius, e.sweep, L, v, w, left);
  };
  auto fits = [&](double v, double allotment, double w, const Privacy& priv) {
    if (priv.on) return fits_private(v, allotment, w, priv.turns);
    const ArcResidualTable& table = *residual_;
    auto mismatch_mm = [&](bool cap) { return mismatch_at(v, cap); };
    if (cfg_.speed_error_s > 0.0 && !(e.spiral > 0.0) && table.covers(e.sweep, L, v)) {
      // offset_mismatch_mm (>= 0) bracketed first, the same answer at less cost: an arc that
      // does not fit without it does not fit, one that fits with its cheap cap fits.
      const double bound = table.error_bound_mm(*precomp_, e.radius, e.sweep, L, v) * w;
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
    if (table.covers(e.sweep, L, v))
      return table.error_bound_mm(*precomp_, e.radius, e.sweep, L, v) * w <= left;
    return precomp_->error_within(e.radius, e.sweep, L, v, w, left);
  };
  // A planar arc (or chain of arcs on one circle): private where arc_privacy holds at the speed
  // tried (docs/tolerance-arc-ends.md, "Private arcs"). Planar: its path no longer than its
  // largest radius's circle (a helix's is longer; a circle's radius is its smaller, up to 0.1 µm
  // below its larger: arc_element).
  const bool plain = cfg_.private_arcs && L <= (e.radius + 1e-4) * e.sweep * (1.0 + 1e-9);
  auto zone_at = [&](double v) -> const ZoneMemo& {
    const ZoneRange r = memo.valid ? zone_range_from(memo.range, e.s0 - v * tau, e.s1 + v * tau)
                                   : zone_range(e.s0 - v * tau, e.s1 + v * tau);
    return zone_values(memo, r, e, false, v * tau);
  };
  auto privacy_at = [&](double v, const ZoneMemo& z) {
    return plain ? arc_privacy(e, v, z) : Privacy{};
  };
  // Set while the arc is planned as one that shares its windows whatever its privacy.
  bool shared_only = false;
  auto fits_shared = [&](double v, double allotment, double w) {
    return fits(v, allotment, w, Privacy{});
  };
  // At v: fits as a private arc (and is one), or as one that shares its windows. Each is
  // monotone in v, so is either; the private arc's is taken where both fit.
  auto fits_privately = [&](double v) {
    const ZoneMemo& z = zone_at(v);
    const Privacy p = privacy_at(v, z);
    if (!p.on) return false;
    if (chain) return fits(v, chain_allotment(v), 1.0, p);
    return fits(v, zone_allotment(share, 1.0, z), z.weight, p);
  };
  auto within = [&](double v) {
    if (!shared_only && fits_privately(v)) return true;
    if (chain) return fits(v, chain_allotment(v), 1.0, Privacy{});
    const ZoneMemo& z = zone_at(v);
    return fits(v, zone_allotment(share, 1.0, z), z.weight, Privacy{});
  };
  // Where the answer is yes, the arc's error (its term and a near circle's extra) is within
  // its allotment at that speed: the bound it leaves (err).
  auto allotted = [&](double v) {
    if (chain) return chain_allotment(v);
    return zone_allotment(
        share, 1.0,
        zone_values(memo, zone_range(e.s0 - v * tau, e.s1 + v * tau), e, false, v * tau));
  };
  // Planned for the table, the drives see the command: a compensated arc's moves at v/A(ωT), up
  // to twice the path's speed, and the drive's speed limit (cap_all on the path) holds for it.
  const double vlim =
      std::min(e.vmax, cfg_.drive_speed_mm_s < kInf
                           ? precomp_->command_limit_mm_s(e.sweep, L, cfg_.drive_speed_mm_s)
                           : precomp_->speed_limit_mm_s(e.sweep, L));
  if (!(vlim > floor)) return 0.0;
  // lo: no better than the curvature cap until shown.
  const double lo = largest_fitting(floor, vlim, within);
  err = allotted(lo);
  const bool lo_private = lo > floor && fits_privately(lo);
  if (private_out != nullptr) *private_out = lo_private;
  if (lo == vlim) return lo;  // fits at its fastest: one speed
  // Its middle faster than its ends: a chain, or an arc cut at zone boundaries (one turn at
  // most) that is a circle (a near circle's extra term is not the ramps'). A private arc runs
  // at one speed (its middle's windows hold its ends' drift: not planned), unless the arc
  // planned as one that shares its windows, its ends slower than its middle, is faster.
  if ((chain || (e.split && !(e.spiral > 0.0))) && ends_out != nullptr && lo > floor) {
    double lo_shared = lo;
    if (lo_private) {
      shared_only = true;
      lo_shared = largest_fitting(floor, vlim, within);
      shared_only = false;
    }
    if (!(lo_shared > floor)) return lo;
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
    std::array<Element::EndCap, 2> slow{};
    const double v_mid =
        slower_ends(e, lo_shared, vlim, share, fits_shared, fits_middle, slow, mid_err);
    if (v_mid > 0.0) {
      // Its time: each slower end over the arc's path its cap holds, the middle at v_mid.
      double t_shared = 0.0, rest = L;
      for (std::size_t k = 0; k < 2; ++k)
        if (slow[k].cap < kInf) {
          const double on_arc = std::clamp(k == 0 ? slow[k].hi - e.s0 : e.s1 - slow[k].lo, 0.0, L);
          t_shared += on_arc / slow[k].cap;
          rest -= on_arc;
        }
      t_shared += std::max(0.0, rest) / v_mid;
      if (!lo_private || t_shared < L / lo) {
        if (private_out != nullptr) *private_out = false;
        *ends_out = slow;
        err = std::max({mid_err, slow[0].err, slow[1].err});
        return v_mid;
      }
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
  // An arc too short for one end slower than its middle (an end is no slower than v_one) runs
  // at one speed. (This also gives up, on such short arcs, a middle faster with both ends as
  // fast, which only a chain whose one speed is its own range's could have.)
  if (!(end_stretch(v_one) < L)) return 0.0;
  const double v_gain = v_one * (1.0 + kSlowerEndsGain);
  if (!fits_middle(v_gain, share, false)) return 0.0;  // its allotment is at most the share
  ZoneMemo mid_memo;
  const double mid_allot = zone_allotment(
      share, 1.0, zone_values(mid_memo, zone_range(e.s0 + 1e-6, e.s1 - 1e-6), e, false));
  // The middle's speed by the table first (cheap: most arcs are then too short for their ends).
  double v_mid =
      largest_fitting(v_one, vlim, [&](double v) { return fits_middle(v, mid_allot, false); });
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
      v_end[k] =
          largest_fitting(v_one, vm, [&](double v) { return fits(v, end_allot(k, v), 1.0); });
      if (v_end[k] < vm) need += end_stretch(v_end[k]) + braking_length_mm(vm, v_end[k], vm);
    }
    return need;
  };
  std::array<double, 2> v_end{};
  if (!(plan_ends(v_mid, v_end) < L)) return 0.0;
  // Then as fast as the simulation allows (the table's bound is kMargin above it), where the
  // ends still fit.
  const double v_sim =
      largest_fitting(v_mid, vlim, [&](double v) { return fits_middle(v, mid_allot, true); });
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

TolerancePlanner::WeighedCorners TolerancePlanner::weighed_corners(const Element& a,
                                                                   double p_stop) {
  const std::size_t ia = index_past_prefix(a);
  WeighedCorners w;
  if (ia == elems_.size()) return w;
  auto plain_corner = [&](const Element& f) {
    return f.kind == ElementKind::Corner && f.untol_for == 0 &&
           f.claim_state != Element::Claim::Claimant;
  };
  // The corner before: decided, nothing after it but the arc since (a run: its first segment,
  // which has no element), and its block (where its pause goes) not yet handed on.
  if (ia > 0 && plain_corner(elems_[ia - 1]) && elems_[ia - 1].decided &&
      (a.kind == ElementKind::Run || elems_[ia - 1].s1 >= a.s0 - 1e-9) && decided_prefix_ == ia &&
      decided_count_ == ia && elems_[ia - 1].stop_cost_s < kInf &&
      elems_[ia - 1].seq >= window_.front().seq)
    w.start = &elems_[ia - 1];
  // The corner after: not decided yet, not claiming, and reached within τ.
  if (ia + 1 < elems_.size() && plain_corner(elems_[ia + 1]) && !elems_[ia + 1].decided &&
      elems_[ia + 1].t0 < a.t1 + filter_.tau_s() && p_stop > elems_[ia + 1].pause0)
    w.end = &elems_[ia + 1];
  return w;
}

TolerancePlanner::Element TolerancePlanner::stopped_corner(const Element& corner, double p_stop,
                                                           bool after) const {
  Element c = corner;
  if (after) {  // decided here, within the tolerance near it
    c.decided = true;
    c.share = share_of(tolerance_near(corner));
    c.claim_state = Element::Claim::Share;
  }
  settle_corner(c, p_stop, corner.vmax, 0.0, after ? p_stop - corner.pause0 : corner.stop_cost_s);
  c.weight = 0.0;
  return c;
}

double TolerancePlanner::cost_decided_aside(Element& c, Element& beside) {
  const Element undecided = c, as_is = beside;
  const std::size_t prefix = decided_prefix_;
  extend_decided_prefix();
  decide(c);
  const double cost = c.cost_s;
  restore(c, undecided);
  decided_prefix_ = prefix;
  restore(beside, as_is);
  return cost;
}

void TolerancePlanner::decide_between_corners(Element& e, double share,
                                              const MismatchReserve& res) const {
  if (e.kind == ElementKind::Arc) {
    decide_arc_beside_claims(e, share, res);
    return;
  }
  decide_run(e, share, res);
  part_zone(e);
}

void TolerancePlanner::decide_weighing_stops(Element& a, double share, const MismatchReserve& res) {
  // (An arc's or a run's: "the arc" below is either; a run's slowing_s is its zone's.)
  // The corners at the arc's two ends share its zone: the one before it (decided just now, its
  // err counted) and the one after it (undecided, counted by its weight, then decided within
  // what the arc left; at its end, or past a tangent line within τ of it at the fastest
  // speeds, where a stop still parts the arc from the tolerances beyond: tolerance_near). A full
  // stop at either (the drain pause: err 0, no weight) leaves the arc more of the share. The four
  // plans are weighed by their costs in the decisions' own terms (the corners' cost_s or
  // stop_cost_s, the arc's slowing_s, the corner after decided on a copy), a plan whose stops alone
  // cost more than the best known not tried; the cheapest is kept.
  const Element before = a;
  decide_between_corners(a, share, res);
  if (!(a.cap < kInf)) return;  // nothing to gain
  const double p_stop = drain_pause_s();
  if (!(p_stop >= 0.0)) return;
  const WeighedCorners corners = weighed_corners(a, p_stop);
  Element* const cs = corners.start;
  Element* const ce = corners.end;
  if (cs == nullptr && ce == nullptr) return;
  const Element start = cs != nullptr ? *cs : Element{}, end = ce != nullptr ? *ce : Element{};
  const Element start_stop = cs != nullptr ? stopped_corner(start, p_stop, false) : start,
                end_stop = ce != nullptr ? stopped_corner(end, p_stop, true) : end;
  const double start_cost = cs != nullptr ? start.cost_s : 0.0;
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
      decide_between_corners(a, share, res);
    } else {
      a.share = share_of(t);
      decide_between_corners(a, a.share, mismatch_reserve(a, t));
    }
  };
  // The corner after decided on a copy beside the arc as it is: its cost.
  auto end_cost = [&] { return cost_decided_aside(*ce, a); };
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

}  // namespace gm
