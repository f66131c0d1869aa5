// TolerancePlanner: the look-ahead window; blocks in, elements decided in turn, pieces out.
#include "planner/tolerance_planner.hpp"

#include "common/units.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>

namespace gm {

TolerancePlanner::TolerancePlanner(const FilterMoments& filter, const PlannerConfig& cfg,
                                   CanonSource& upstream)
    : filter_(filter), cfg_(cfg), merger_(upstream) {
  const std::vector<double>& h = filter_.weights();
  if (std::all_of(h.begin(), h.end(), [](double w) { return w >= 0.0; })) {
    const double n = static_cast<double>(filter_.order()), m = filter_.centre();
    tent_s_ = filter_.period_s() * std::max(m, n - m);
    dense_runs_ = true;
  }
  if (cfg_.precompensate_arcs && filter_.overshoot_s() == 0.0 && filter_.undershoot_s() == 0.0) {
    precomp_.emplace(filter_.weights(), filter_.period_s());
    if (!precomp_->enabled())
      precomp_.reset();
    else {
      residual_.emplace(*precomp_);
      residual_private_.emplace(*precomp_, ArcPrecompCheck::Judging::Private);
      residual_drift_.emplace(*precomp_, ArcPrecompCheck::Judging::PrivateDrift);
    }
  }
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
  // whole turn, so its joins stop. Not a join between two arcs that turn the same way in one
  // plane with radii within kG61CurveRatio of each other (a helix written as half turns, CAM
  // biarcs): the curvature the filter's window sees stays within the tighter arc's, as on one
  // arc, and the chain's own ends keep the rule. Not with pre-compensated G61 arcs either, whose
  // corrections blend out at every block end.
  const double tau = filter_.tau_s();
  const bool curve_goes_on = prev.m.kind == MotionKind::Arc && next.kind == MotionKind::Arc &&
                             !cfg_.precompensate_g61_arcs && one_curve(prev.g, next_g);
  if (!curve_goes_on) {
    if (prev.m.kind == MotionKind::Arc && prev.g.length_mm < prev.vmax * tau) return false;
    if (next.kind == MotionKind::Arc && next_g.length_mm < v_next * tau) return false;
  }
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

double TolerancePlanner::emit_horizon_t(const Block& b) const {
  const Element* chain = chain_of(b);
  return chain != nullptr ? std::max(b.t1, chain->t1) : b.t1;
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
  // need the blocks within τ after them; so do a short run's first vertices, pushed as such
  // corners when decide_reachable closes the run (up to 2τ ahead of what it decides).
  const bool short_run = run_.open && run_.vertices < kMinRunVertices;
  const double reach = claim_candidates_ > 0 || short_run ? 2.0 * tau : tau;
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
    case ElementKind::Run:
      if (weigh_depth_ == 0)
        decide_weighing_stops(e, share, res);
      else
        decide_between_corners(e, share, res);
      return;
    case ElementKind::Corner:
      if (weigh_depth_ == 0 && e.untol_for == 0) {
        decide_corner_weighing(e, tol, share, res);
        return;
      }
      [[fallthrough]];
    case ElementKind::Stop:
      decide_corner(e, share, res);
      part_zone(e);
      return;
  }
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
  const std::size_t first_piece = ready_.size();
  emit_pieces(b, comp_v, chain, own != nullptr && own->comp_private && comp_v > 0.0);
  const std::size_t last_piece = ready_.size() - 1;
  if (const double ramp = override_ramp_before(b); ramp > 0.0)
    for (std::size_t i = first_piece; i <= last_piece; ++i)
      std::get<Motion>(ready_[i].canon).override_ramp_mm_s = ramp;
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

double TolerancePlanner::override_ramp_before(const Block& b) const {
  // The first private arc starting within its reach (v_p·τ) after b's end, b a line.
  if (b.m.kind != MotionKind::Line || !precomp_) return 0.0;
  const double tau = filter_.tau_s();
  for (const Element& e : elems_) {
    if (e.s0 < b.s1 - 1e-9) continue;
    if (e.kind == ElementKind::Arc && e.comp_private && e.comp_speed > 0.0 &&
        e.s0 - b.s1 <= e.comp_speed * tau + 1e-9)
      return precomp_->rule().speed_step_mm_s(e.comp_speed);
    if (e.s0 > b.s1 + e.vmax * tau) break;  // (in path order)
  }
  return 0.0;
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
