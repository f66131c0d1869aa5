// TolerancePlanner: look-ahead window, per-element budgets, speed caps by zone, corner pauses.
#include "planner/tolerance_planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gm {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMinTurn = 1e-9;  // |Δu| below this is a straight continuation

double min_positive(double a, double b) {
  if (a > 0.0 && b > 0.0) return std::min(a, b);
  return a > 0.0 ? a : b;
}

}  // namespace

TolerancePlanner::TolerancePlanner(const FilterMoments& filter, const PlannerConfig& cfg,
                                   CanonSource& upstream)
    : filter_(filter), cfg_(cfg), upstream_(upstream) {
  for (int k = 0; k <= 2 * filter_.order(); ++k)
    grid_d_.push_back(filter_.corner_moment_s(0.5 * k * filter_.period_s()));
}

void TolerancePlanner::pull() {
  if (!upstream_.next(scratch_)) {
    ended_ = true;
    return;
  }
  const Motion* m = std::get_if<Motion>(&scratch_);
  BlockGeometry g;
  if (m != nullptr) g = BlockGeometry::of(*m);
  if (m == nullptr || !(g.length_mm > 0.0)) {  // not a block of the path
    if (window_.empty()) {
      ready_.push_back(scratch_);
      return;
    }
    Block& last = window_.back();
    if (const auto* d = std::get_if<Dwell>(&scratch_)) last.dwell_after_s += d->seconds;
    if (const auto* e = std::get_if<Event>(&scratch_); e != nullptr && e->kind == EventKind::End)
      last.stop_after = true;
    last.after.push_back(scratch_);
    return;
  }
  const double tau = filter_.tau_s();
  Block b;
  b.m = *m;
  b.g = g;
  b.seq = ++seq_;
  const double L = g.length_mm;
  if (m->kind == MotionKind::Rapid)
    b.v100 = cfg_.rapid_mm_min / 60.0;
  else if (m->inverse_time_s > 0.0)
    b.v100 = L / m->inverse_time_s;
  else
    b.v100 = m->feed_mm_min / 60.0;
  b.v100 = std::max(b.v100, 1e-9);
  b.vmax = b.v100 * cfg_.max_override;
  b.u0 = g.tangent_at_fraction(0.0);
  b.u1 = g.tangent_at_fraction(1.0);
  b.s0 = s_end_;
  b.s1 = s_end_ + L;
  double gap_s = 0.0;
  const Block* prev = window_.empty() ? nullptr : &window_.back();
  if (prev != nullptr) gap_s = prev->dwell_after_s + (prev->stop_after ? tau : 0.0);
  b.t0 = t_end_ + gap_s;
  b.t1 = b.t0 + L / b.vmax;
  s_end_ = b.s1;
  t_end_ = b.t1;

  if (prev != nullptr && !prev->stop_after) {
    const double turn = (b.u0 - prev->u1).norm();
    const double tol = min_positive(prev->m.path_tolerance_mm, b.m.path_tolerance_mm);
    if (turn > kMinTurn && tol > 0.0) {
      Element e;
      e.seq = prev->seq;
      e.t0 = prev->t1;
      e.t1 = b.t0;
      e.s0 = e.s1 = prev->s1;
      e.tol_mm = tol;
      e.turn = turn;
      e.pause0 = prev->dwell_after_s;
      e.vmax = std::max(prev->vmax, b.vmax);
      e.v100 = std::max(prev->v100, b.v100);
      elems_.push_back(e);
    }
  }
  if (m->kind == MotionKind::Arc && m->path_tolerance_mm > 0.0) {
    const double r = std::min(g.r0_mm, g.r1_mm);
    Element e;
    e.arc = true;
    e.seq = b.seq;
    e.t0 = b.t0;
    e.t1 = b.t1;
    e.s0 = b.s0;
    e.s1 = b.s1;
    e.tol_mm = m->path_tolerance_mm;
    e.kappa = r > 0.0 ? 1.0 / r : kInf;
    e.vmax = b.vmax;
    e.v100 = b.v100;
    elems_.push_back(e);
  }
  if (m->path_mode != PathMode::Continuous) b.stop_after = true;
  window_.push_back(std::move(b));
}

bool TolerancePlanner::lookahead_enough() const {
  if (ended_ || window_.size() >= cfg_.capacity) return true;
  const double tau = filter_.tau_s();
  const Block& f = window_.front();
  double need = f.t1 + 2.0 * tau;
  for (const Element& e : elems_)
    if (!e.decided && e.t0 < f.t1 + tau) need = std::max(need, e.t1 + tau);
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

void TolerancePlanner::decide(Element& e) {
  const double tau = filter_.tau_s();
  // The tolerance: the smallest among the elements that can share a window with e and the
  // blocks the interpolator is in while the filter still holds e (each judged by its own).
  double tol = e.tol_mm;
  for (const Element& f : elems_) {
    const double gap = f.t0 > e.t1 ? f.t0 - e.t1 : (e.t0 > f.t1 ? e.t0 - f.t1 : 0.0);
    if (gap < tau) tol = std::min(tol, f.tol_mm);
  }
  for (const Block& b : window_)
    if (b.t1 >= e.t0 && b.t0 < e.t1 + tau && b.m.path_tolerance_mm > 0.0)
      tol = std::min(tol, b.m.path_tolerance_mm);
  const double margin = std::min(cfg_.rounding_mm, 0.5 * tol);
  const double share = tol - margin;

  // n: e and the elements whose contributions can overlap e's in time. Times are fastest
  // travel plus the pauses planned before (decided elements keep theirs); an element after e
  // is further delayed by the pause `added` planned at e; its own pause is taken as 0.
  const double off = added_pause_s_;
  auto count = [&](double e0, double e1, double added) {
    int n = 1;
    for (const Element& f : elems_) {
      if (&f == &e) continue;
      double f0, f1;
      if (f.decided) {
        f0 = f.a0, f1 = f.a1;
      } else {
        f0 = (f.arc ? f.t0 : f.t1) + off + added;  // corner: once it leaves the vertex
        f1 = (f.arc ? f.t1 : f.t0) + tau + off + added;
      }
      if (e0 < f1 + 1e-9 && f0 < e1 + 1e-9) ++n;
    }
    return n;
  };

  e.decided = true;
  e.cap = kInf;
  if (e.arc) {
    e.a0 = e.t0 + off;
    e.a1 = e.t1 + tau + off;
    const double budget = share / count(e.a0, e.a1, 0.0);
    const double v = std::sqrt(2.0 * budget / (e.kappa * filter_.variance_s2()));
    if (v < e.vmax) e.cap = v;
    e.z0 = zone_back(e.s0, tau, e.cap);
    e.z1 = zone_fwd(e.s1, tau, e.cap);
    return;
  }
  // Corner: the pause P (at least what the program already dwells) and cap V with
  // |Δu|·V·D(P) <= share / n(P) that cost the least time: the pause added plus the slowing in
  // the zones, (τ − P) of time either side at V instead of the 100 % speed.
  double best_cost = kInf, best_p = e.pause0, best_v = 0.0;
  auto consider = [&](double p, double d) {
    double v = kInf;
    if (d > 0.0) {
      const int n = count(e.t0 + off + p, e.t0 + off + tau, p - e.pause0);
      v = share / n / (e.turn * d);
    }
    v = std::min(v, e.vmax);
    const double slow = std::max(0.0, 1.0 - v / e.v100);
    const double cost = (p - e.pause0) + 2.0 * std::max(0.0, tau - p) * slow;
    if (cost < best_cost - 1e-12) {
      best_cost = cost;
      best_p = p;
      best_v = v;
    }
  };
  consider(e.pause0, filter_.corner_moment_s(e.pause0));
  for (std::size_t k = 0; k < grid_d_.size(); ++k) {
    const double p = 0.5 * static_cast<double>(k) * filter_.period_s();
    if (p > e.pause0) consider(p, grid_d_[k]);
  }
  e.pause = best_p;
  e.a0 = e.t0 + off + best_p;
  e.a1 = e.t0 + off + tau;
  added_pause_s_ += best_p - e.pause0;
  if (best_v < e.vmax) e.cap = best_v;
  const double zt = std::max(0.0, tau - best_p);
  e.z0 = zone_back(e.s0, zt, e.cap);
  e.z1 = zone_fwd(e.s1, zt, e.cap);
  ++stats_.corners;
  if (best_p > e.pause0) {
    ++stats_.paused_corners;
    stats_.pause_total_s += best_p - e.pause0;
  }
}

void TolerancePlanner::emit_front() {
  const double tau = filter_.tau_s();
  if (!ended_ && window_.size() >= cfg_.capacity && !window_.back().stop_after) {
    window_.back().stop_after = window_.back().forced_stop = true;
    ++stats_.forced_stops;
  }
  Block& b = window_.front();
  for (Element& e : elems_)
    if (!e.decided && e.t0 < b.t1 + tau) decide(e);

  // Pieces of the block between zone boundaries, each with the smallest cap over it.
  const bool is_arc = b.m.kind == MotionKind::Arc;
  std::vector<double> cuts{b.s0, b.s1};
  if (!is_arc)
    for (const Element& e : elems_)
      if (e.decided && e.cap < kInf)
        for (double z : {e.z0, e.z1})
          if (z > b.s0 && z < b.s1) cuts.push_back(z);
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  struct Piece {
    double a, c, cap;
  };
  std::vector<Piece> pieces;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double a = cuts[i], c = cuts[i + 1];
    if (c - a < 1e-9 && !pieces.empty()) {  // a sliver: joins the piece before
      pieces.back().c = c;
      continue;
    }
    double cap = kInf;
    for (const Element& e : elems_) {
      if (!e.decided || !(e.cap < kInf)) continue;
      const bool covers =
          is_arc ? (e.z0 < c && e.z1 > a) : (e.z0 <= 0.5 * (a + c) && 0.5 * (a + c) <= e.z1);
      if (covers) cap = std::min(cap, e.cap);
    }
    if (!pieces.empty() && pieces.back().cap == cap)
      pieces.back().c = c;
    else
      pieces.push_back({a, c, cap});
  }
  // No piece shorter than one sample of travel at the fastest speed: the contour measurement
  // sees one block per sample (the one the sample ends in), so such a piece would be skipped by
  // it. A merged piece takes the smaller cap (never faster than planned).
  const double min_piece = 1.01 * b.vmax * filter_.period_s();
  for (std::size_t i = 0; pieces.size() > 1 && i < pieces.size();) {
    if (pieces[i].c - pieces[i].a >= min_piece) {
      ++i;
      continue;
    }
    const std::size_t j = i + 1 < pieces.size() ? i + 1 : i - 1;  // the neighbour it joins
    const std::size_t lo = std::min(i, j), hi = std::max(i, j);
    pieces[lo] = {pieces[lo].a, pieces[hi].c, std::min(pieces[lo].cap, pieces[hi].cap)};
    pieces.erase(pieces.begin() + static_cast<std::ptrdiff_t>(hi));
    i = lo;
  }
  const double L = b.s1 - b.s0;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    Motion p = b.m;
    const Piece& q = pieces[i];
    if (pieces.size() > 1) {
      p.start_mm = i == 0 ? b.m.start_mm : b.g.at_fraction((q.a - b.s0) / L);
      p.end_mm = i + 1 == pieces.size() ? b.m.end_mm : b.g.at_fraction((q.c - b.s0) / L);
      if (b.m.inverse_time_s > 0.0) p.inverse_time_s = b.m.inverse_time_s * (q.c - q.a) / L;
    }
    if (q.cap < b.vmax * (1.0 - 1e-12)) {
      p.speed_cap_mm_s = q.cap;
      ++stats_.capped_pieces;
    }
    ready_.push_back(p);
  }
  for (const Element& e : elems_)
    if (!e.arc && e.seq == b.seq && e.pause > e.pause0 + 1e-12)
      ready_.push_back(Dwell{b.m.line, e.pause - e.pause0});
  if (b.forced_stop) ready_.push_back(Dwell{b.m.line, tau});
  for (Canon& c : b.after) ready_.push_back(std::move(c));
  window_.pop_front();
  // Elements that can no longer reach a block still to come, nor be counted by one.
  const double keep_from = window_.empty() ? kInf : window_.front().t0 - 2.0 * tau;
  while (!elems_.empty() && elems_.front().decided && elems_.front().t1 < keep_from)
    elems_.pop_front();
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
  out = std::move(ready_.front());
  ready_.pop_front();
  return true;
}

}  // namespace gm
