// TolerancePlanner's zones: the path an element shares, the weights, errs and claims in it.
#include "planner/tolerance_planner.hpp"

#include "common/units.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>

namespace gm {

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
                                                                const Element& e, bool with_claims,
                                                                double span) const {
  const bool new_range = !memo.valid || !(r == memo.range);
  if (!new_range && (span == memo.span || (span >= 0.0 && memo.span >= 0.0 &&
                                           span >= memo.span_lo && span <= memo.span_hi))) {
    memo.span = span;
    return memo;
  }
  if (new_range) {
    memo.range = r;
    memo.valid = true;
    memo.parted = parted(r, e);
    memo.zone_weight = range_weight(memo.parted);
    memo.zone_weight_all = range_weight_all(memo.parted);
    memo.decided = range_decided(memo.parted, e);
    memo.claims = with_claims ? range_claims(memo.parted) : 0.0;
  }
  memo.span = span;
  const WindowWeights w = span >= 0.0 ? window_weights(memo, e, span)
                                      : WindowWeights{memo.zone_weight, memo.zone_weight_all};
  memo.weight = w.undecided;
  memo.weight_all = w.all;
  memo.span_lo = w.span_lo;
  memo.span_hi = w.span_hi;
  return memo;
}

TolerancePlanner::WindowWeights TolerancePlanner::window_weights(const ZoneMemo& z,
                                                                 const Element& e,
                                                                 double span) const {
  // A window [a, a + span] overlaps f when f.s1 > a − 1e-9 and f.s0 < a + span + 1e-9 (the
  // zone tests' slack), and overlaps e for a in [e.s0 − span, e.s1]. Each f counts for a in an
  // interval ending at f.s1: the sum is largest at one of those ends or at e.s1. The elements
  // are in path order (s0 and s1 both ascending), so those f are a range [lo, hi), walked once.
  // Every test that involves the span narrows the spans [span_lo, span_hi] for which all tests
  // come out the same, so the same sums: a bisection reuses them (kMargin keeps the bounds
  // clear of the tests' rounding).
  constexpr double kMargin = 1e-7;
  WindowWeights best;
  const ZoneRange r = z.parted;
  if (r.first == r.last) return best;
  const double a0 = e.s0 - span;
  const Element& first = elems_[r.first];
  // One window from the first element's end holds the whole range: its weights.
  const double first_s1 = first.s1, last_s0 = elems_[r.last - 1].s0;
  if (first_s1 >= a0 && last_s0 < first_s1 + span + 1e-9) {
    best.undecided = z.zone_weight;
    best.all = z.zone_weight_all;
    best.span_lo = std::max(e.s0 - first_s1, last_s0 - first_s1 - 1e-9) + kMargin;
    return best;
  }
  auto at_least = [&](double bound) { best.span_lo = std::max(best.span_lo, bound + kMargin); };
  auto at_most = [&](double bound) { best.span_hi = std::min(best.span_hi, bound - kMargin); };
  const std::size_t from = std::max(r.first, decided_prefix_);
  auto cum = [&](std::size_t i) { return i == elems_.size() ? weight_total_ : elems_[i].cum; };
  std::size_t lo = r.first, hi = r.first;
  auto hold = [&](double a) {
    while (lo < r.last && !(elems_[lo].s1 > a - 1e-9)) ++lo;
    for (; hi < r.last; ++hi) {
      const double bound = elems_[hi].s0 - a - 1e-9;
      if (!(elems_[hi].s0 < a + span + 1e-9)) {
        at_most(bound);
        break;
      }
      at_least(bound);
    }
    if (hi > lo) best.all = std::max(best.all, cum(hi) - cum(lo));
    const std::size_t f = std::max(lo, from);
    if (hi > f) best.undecided = std::max(best.undecided, cum(hi) - cum(f));
  };
  for (std::size_t i = r.first; i < r.last && elems_[i].s1 < e.s1; ++i) {
    if (!(elems_[i].s1 >= a0)) {
      at_most(e.s0 - elems_[i].s1);
      continue;
    }
    at_least(e.s0 - elems_[i].s1);
    hold(elems_[i].s1);
  }
  hold(e.s1);
  return best;
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
    // (its cap not chosen yet).
    const double share = share_of(tol) - mismatch_reserve(g, tol).ceiling_mm();
    // Claims active with g lie within τ of it; those after g are assigned after it and count g.
    std::size_t near_from = claim_cursor_;
    while (near_from > 0 && elems_[near_from - 1].t1 >= g.t0 - tau) --near_from;
    // At its fastest speed (only the smallest turns, or where no override can run the path
    // faster than 100 %), else at 100 % feed; its zone capped at that speed either way.
    for (const double v : {g.vmax, std::min(g.vmax, g.v100)}) {
      if (v == g.vmax && g.turn > kClaimFreeTurn && g.v100 < g.vmax) continue;
      g.claim = v * corner_moment(g.pause0) * g.turn;
      g.claim_half = tent_s_ * v;
      // The claims' sum at the instants g is active: piecewise linear in the window's mean x,
      // largest at a tent's peak or at the ends of g's (with the whole claims: g's vertex).
      auto claims_at = [&](double x) {
        double near = 0.0;
        for (std::size_t i = claim_cursor_; i-- > near_from;)
          if (elems_[i].claim_state == Element::Claim::Claimant) near += claim_at(elems_[i], x);
        return near + claim_at(g, x);
      };
      double worst = claims_at(g.s0);
      if (tent_s_ > 0.0) {
        worst = std::max({worst, claims_at(g.s0 - g.claim_half), claims_at(g.s0 + g.claim_half)});
        for (std::size_t i = near_from; i < claim_cursor_; ++i)
          if (elems_[i].claim_state == Element::Claim::Claimant &&
              std::abs(elems_[i].s0 - g.s0) < g.claim_half)
            worst = std::max(worst, claims_at(elems_[i].s0));
      }
      if (worst > 0.5 * share) continue;
      g.claim_state = Element::Claim::Claimant;
      // The claim (and its tent) needs every advance in g's windows at most v·T, beside
      // blocks faster than its own too: its zone is capped at v even at its fastest speed.
      g.claim_cap = v;
      ++claimants_;
      break;
    }
    if (g.claim_state != Element::Claim::Claimant) g.claim = g.claim_half = 0.0;
  }
}

double TolerancePlanner::zone_claims(double z0, double z1) const {
  if (claimants_ == 0) return 0.0;
  return range_claims(zone_range(z0, z1));
}

double TolerancePlanner::claim_at(const Element& c, double x) const {
  if (!(c.claim_half > 0.0)) return c.claim;  // no tents (negative weights)
  return c.claim * std::max(0.0, 1.0 - std::abs(x - c.s0) / c.claim_half);
}

double TolerancePlanner::range_claims(ZoneRange r) const {
  if (claimants_ == 0) return 0.0;
  const double tau = filter_.tau_s();
  const auto first = elems_.begin() + static_cast<std::ptrdiff_t>(r.first);
  const auto last = elems_.begin() + static_cast<std::ptrdiff_t>(r.last);
  double best = 0.0;
  if (tent_s_ > 0.0) {
    // The tents' sum is piecewise linear in the window's mean, largest at a peak: at each
    // claimant's vertex, the tents of the claimants within τ of it (the others cannot share a
    // window with it).
    auto lo = first;
    for (auto it = first; it != last; ++it) {
      if (it->claim_state != Element::Claim::Claimant) continue;
      while (lo->t1 < it->t0 - tau) ++lo;
      double sum = 0.0;
      for (auto j = lo; j != last && !(j->t0 > it->t1 + tau); ++j)
        if (j->claim_state == Element::Claim::Claimant) sum += claim_at(*j, it->s0);
      best = std::max(best, sum);
    }
    return best;
  }
  double sum = 0.0;
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

}  // namespace gm
