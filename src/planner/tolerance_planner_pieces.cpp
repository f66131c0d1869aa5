// TolerancePlanner's pieces: blocks cut at zone boundaries into capped pieces, braked to.
#include "planner/tolerance_planner.hpp"

#include "common/units.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>

namespace gm {

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
  // (Motion::comp_exit_speed_mm_s). A piece too short for that runs at the fastest speed it can
  // brake from within its length (a cap like any zone's, below its plan), or at the next one's
  // cap when it cannot brake by one step.
  std::vector<Piece>& pieces = pieces_;
  if (!(comp_v > 0.0) || pieces.size() < 2) return;
  for (std::size_t i = pieces.size() - 1; i-- > 0;) {
    const double plan = pieces[i].plan_or(comp_v);
    const double from = std::min(pieces[i].cap, plan),
                 to = std::min(pieces[i + 1].cap, pieces[i + 1].plan_or(comp_v));
    if (!(to < from)) continue;
    const double len = pieces[i].c - pieces[i].a;
    if (len < braking_length_mm(from, to, plan)) {
      const double v = fastest_braking_mm_s(to, len, plan);
      pieces[i].cap = v > to ? v : pieces[i + 1].cap;
    }
  }
}

double TolerancePlanner::fastest_braking_mm_s(double to, double len, double comp_v) const {
  // to + m steps for the largest m whose ramp fits (braking_length_mm counts ceil of the steps:
  // the speed sits just below m steps so that it counts m); m is at most the ramp's N + 1.
  const double step = precomp_->rule().speed_step_mm_s(comp_v);
  auto speed = [&](int m) { return to + m * step * (1.0 - 1e-9); };
  int m = 0;
  while (m <= precomp_->rule().ramp_samples() && braking_length_mm(speed(m + 1), to, comp_v) <= len)
    ++m;
  return speed(m);
}

double TolerancePlanner::braking_length_mm(double from, double to, double comp_v) const {
  // The ramp's samples from `from` down to `to`, one more at `from` (the sample it starts in).
  const double step = precomp_->rule().speed_step_mm_s(comp_v), T = filter_.period_s();
  const double m = std::ceil((from - to) / step);
  return T * ((m + 1.0) * to + step * (m + 1.0) * (m + 2.0) / 2.0);
}

void TolerancePlanner::emit_pieces(const Block& b, double comp_v, const Element* chain,
                                   bool comp_private) {
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
    p.comp_private = comp_private;
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

}  // namespace gm
