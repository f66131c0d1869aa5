// ArcPrecompCheck: the isolated compensated arc and the ramp's transient, through the weights.
#include "planner/arc_precomp.hpp"

#include "common/isa.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <utility>

namespace gm {
namespace {

constexpr std::size_t kCacheSlots = 256;  // a power of two
constexpr double kNoLimit = std::numeric_limits<double>::infinity();

std::size_t cache_slot(double r, double sweep, double len, double v) {
  std::uint64_t h = 0x9e3779b97f4a7c15ULL;
  for (double x : {r, sweep, len, v}) {
    h ^= std::bit_cast<std::uint64_t>(x);
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
  }
  return static_cast<std::size_t>(h) & (kCacheSlots - 1);
}

// The outputs of ArcPrecompCheck::kBatch (4) windows of n weights h whose newest samples are
// at ring slots 0..3 (xy: the slots' (x, y) pairs in a row, p their in-plane lengths): lane j
// sums h_i·x_{i+j} for i = 0..n−1 in this order, a product and a sum each (no fused
// multiply-add), so each output is window_output's bit for bit whatever the vector width. Four
// windows at once keep four sums in flight where one would wait on each addition.
using Lanes = double __attribute__((vector_size(32)));
__attribute__((always_inline)) inline void batch_sums(const double* h, std::size_t n,
                                                      const double* xy, const double* p,
                                                      double* out_xy, double* out_p) {
  Lanes a01 = {0.0, 0.0, 0.0, 0.0}, a23 = a01, ap = a01;
  for (std::size_t i = 0; i < n; ++i) {
    const Lanes hv = {h[i], h[i], h[i], h[i]};
    Lanes x01, x23, pv;
    std::memcpy(&x01, xy + 2 * i, sizeof x01);      // slots i, i + 1
    std::memcpy(&x23, xy + 2 * i + 4, sizeof x23);  // slots i + 2, i + 3
    std::memcpy(&pv, p + i, sizeof pv);
    const Lanes m01 = hv * x01, m23 = hv * x23, mp = hv * pv;
    a01 += m01;
    a23 += m23;
    ap += mp;
  }
  std::memcpy(out_xy, &a01, sizeof a01);
  std::memcpy(out_xy + 4, &a23, sizeof a23);
  std::memcpy(out_p, &ap, sizeof ap);
}
__attribute__((target("avx2"))) void batch_sums_avx2(const double* h, std::size_t n,
                                                     const double* xy, const double* p,
                                                     double* out_xy, double* out_p) {
  batch_sums(h, n, xy, p, out_xy, out_p);
}
void batch_sums_portable(const double* h, std::size_t n, const double* xy, const double* p,
                         double* out_xy, double* out_p) {
  batch_sums(h, n, xy, p, out_xy, out_p);
}

}  // namespace

ArcPrecompCheck::ArcPrecompCheck(const std::vector<double>& weights, double period_s,
                                 double line_ratio, double near_s, bool end_rows)
    : h_(weights),
      period_s_(period_s),
      rule_(weights, period_s, end_rows),
      line_ratio_(line_ratio),
      near_s_(near_s) {
  // The window and the kBatch − 1 samples before it, each slot twice (the outputs read a window
  // in a row).
  ring_.resize(2 * ring_slots());
  ring_p_.resize(2 * ring_slots());
  use_avx2_ = active_isa() != Isa::Portable;
  fork_ring_.resize(ring_.size());
  fork_ring_p_.resize(ring_p_.size());
  cache_.resize(kCacheSlots);
  for (auto& f : knot_factor_) f.fill(std::numeric_limits<double>::quiet_NaN());
  nonnegative_ = std::all_of(h_.begin(), h_.end(), [](double h) { return h >= 0.0; });
  double mean = 0.0, second = 0.0;
  for (std::size_t i = 0; i < h_.size(); ++i) {
    const double t = static_cast<double>(i) * period_s_;
    mean += h_[i] * t;
    second += h_[i] * t * t;
    for (std::size_t j = 0; j < h_.size(); ++j)
      spread_ += std::abs(h_[i]) * std::abs(h_[j]) *
                 std::abs(static_cast<double>(i) - static_cast<double>(j));
  }
  variance_s2_ = second - mean * mean;
}

double ArcPrecompCheck::spiral_mm(double r_min, double r_max, double sweep_abs_rad,
                                  double length_mm, double v_plan, double circle_mm) const {
  const double dr = r_max - r_min, r = r_min, L = length_mm;
  const double M = v_plan * period_s_ * spread_;
  const double U = v_plan * v_plan * variance_s2_ / (2.0 * r);
  const double omega = v_plan * sweep_abs_rad / L;
  const double offset = rule_.correction_mm(r_max, omega) *
                        rule_.largest_offset_factor(omega * period_s_, distance_rows());
  return dr * (M / (2.0 * r) + M / L + (circle_mm + U) / (2.0 * r) + M * offset / (L * r));
}

double ArcPrecompCheck::offset_mismatch_cap_mm(double radius_mm, double sweep_abs_rad,
                                               double length_mm, double v_plan,
                                               double speed_error_s, double step_error,
                                               double fir_variation) const {
  const double rows = rule_.rows_weight(length_mm, v_plan);
  if (rows > 0.0 && !(fir_variation > 0.0)) return kNoLimit;
  const double T = period_s_, x = v_plan * sweep_abs_rad / length_mm * T;
  const double c = radius_mm * rule_.correction_ratio_cap(x);  // |c(v)| for every v <= v_p
  const double steady = speed_error_s / T * (c * x + 2.0 * c);
  // (1 + 10⁻⁹: over the exact term's roundings.)
  const double blend = (steady + step_error * 2.0 * c) * (1.0 + 1e-9);
  if (!(rows > 0.0)) return blend;
  // K at the knots up to the first at or past x (beyond the last, clamped to it).
  const double limit = rule_.limit_omega_t();
  double K = 0.0;
  auto& factors = knot_factor_[distance_rows() ? 1 : 0];
  for (std::size_t j = 0; j < factors.size(); ++j) {
    if (std::isnan(factors[j]))
      factors[j] = rule_.largest_offset_factor(ArcEndRows::kRateKnots[j] * limit, distance_rows());
    K = std::max(K, factors[j]);
    if (ArcEndRows::kRateKnots[j] * limit >= x) break;
  }
  const double with_rows =
      steady + step_error * fir_variation * (ArcEndRows::kSpan + 1) * (K * c + c);
  return std::max(with_rows * (1.0 + 1e-9), blend);
}

double ArcPrecompCheck::offset_mismatch_mm(double radius_mm, double sweep_abs_rad, double length_mm,
                                           double v_plan, double speed_error_s, double step_error,
                                           double fir_variation) const {
  const double rows = rule_.rows_weight(length_mm, v_plan);
  if (rows > 0.0 && !(fir_variation > 0.0)) return kNoLimit;
  const double T = period_s_, rate = sweep_abs_rad / length_mm * T;  // ωT per mm/s
  auto c_at = [&](double v) {
    return v > 0.0 ? radius_mm * (1.0 / rule_.gain(v * rate) - 1.0) : 0.0;
  };
  // |c| and the ramp's steps of c on a grid of a quarter step of speeds up to v_p (a gain that
  // peaks above 1 gives c < 0, and |c| need not be largest at v_p).
  const double step = rule_.speed_step_mm_s(v_plan);
  double c_max = 0.0, dc = 0.0;
  for (double v = v_plan; v > 0.0; v -= 0.25 * step) {
    c_max = std::max(c_max, std::abs(c_at(v)));
    dc = std::max(dc, std::abs(c_at(v) - c_at(v - step)));
  }
  const double x = v_plan * rate;
  // o = s + p: s = c·n, the steady offset, turning and changing with c on every sample (M/T).
  const double steady = speed_error_s / T * (c_max * x + dc);
  // The radial blend's p, from −c to 0 and back at the ends: E times that variation (the
  // filter's taps being >= 0, the servos see no more of it).
  const double blend = steady + step_error * 2.0 * c_max;
  if (!(rows > 0.0)) return blend;
  // The rows' p: at most (K + 1)/2·|c| on each of kSpan + 1 samples per end (the advances count
  // samples; K = largest_offset_factor), which the filter smooths before the servos see it:
  // Δ(h ∗ p) = (Δh) ∗ p, at most fir_variation·Σ|p| (E times it). K·|c| over the rates up to x
  // on 32 intervals of [0, x] split at the rows' rate knots (the shapes are linear in the rate
  // between knots, so within an interval at most its ends' K), times the interval's largest |c|.
  double Kc = 0.0, K_last = 1.0, c_last = 0.0;
  std::array<double, 32 + ArcEndRows::kRateKnots.size()> at{};
  std::size_t n = 0;
  for (int j = 1; j <= 32; ++j) at[n++] = x * j / 32.0;
  for (const double knot : ArcEndRows::kRateKnots)
    if (knot * rule_.limit_omega_t() < x) at[n++] = knot * rule_.limit_omega_t();
  std::sort(at.begin(), at.begin() + static_cast<std::ptrdiff_t>(n));
  for (std::size_t k = 0; k < n; ++k) {
    const double K = rule_.largest_offset_factor(at[k], distance_rows()),
                 c = std::abs(c_at(at[k] / rate));
    Kc = std::max(Kc, std::max(K, K_last) * std::max(c, c_last));
    K_last = K, c_last = c;
  }
  const double with_rows =
      steady + step_error * fir_variation * (ArcEndRows::kSpan + 1) * (Kc + c_max);
  return rows * with_rows + (1.0 - rows) * blend;
}

double ArcPrecompCheck::speed_limit_mm_s(double sweep_abs_rad, double length_mm) const {
  if (!enabled() || !(sweep_abs_rad > 0.0)) return 0.0;
  return rule_.limit_omega_t() / period_s_ * length_mm / sweep_abs_rad;
}

double ArcPrecompCheck::command_limit_mm_s(double sweep_abs_rad, double length_mm,
                                           double command_mm_s) const {
  // The command's steady speed v/A(v·T·|θ|/L) grows with v (A falls from 1): bisection.
  auto within = [&](double v) {
    return v / rule_.gain(v * period_s_ * sweep_abs_rad / length_mm) <= command_mm_s;
  };
  const double hi = speed_limit_mm_s(sweep_abs_rad, length_mm);
  if (!(hi > 0.0) || within(hi)) return hi;
  double lo = 0.0, up = hi;
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + up);
    (within(mid) ? lo : up) = mid;
  }
  return lo;
}

Eigen::Vector2d ArcPrecompCheck::point(double p) const {
  if (p <= 0.0) return {p, 0.0};
  if (p < lp_) return {r_ * std::sin(p / r_), r_ - r_ * std::cos(p / r_)};
  const double d = p - lp_;
  return {end_sin_r_ + d * end_cos_, end_1mcos_r_ + d * end_sin_};
}

void ArcPrecompCheck::put(std::size_t& head, const Eigen::Vector2d& x, double p) const {
  const std::size_t m = ring_slots();
  head = head == 0 ? m - 1 : head - 1;  // newest at head
  ring_[head] = ring_[head + m] = x;
  ring_p_[head] = ring_p_[head + m] = p;
}

void ArcPrecompCheck::window_output(std::size_t head, Eigen::Vector2d& y, double& pbar) const {
  // Σ h_i·x_i and Σ h_i·p_i, i = 0..n−1 in this order, x_i at slot head + i (each slot is
  // stored twice, so the window lies in a row). Local sums (the outputs may alias the rings for
  // all the compiler knows).
  const std::size_t n = h_.size();
  const double* h = h_.data();
  const double* x = ring_[head].data();  // x then y of each slot, in a row
  const double* p = ring_p_.data() + head;
  double yx = 0.0, yy = 0.0, pb = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    yx += h[i] * x[2 * i];
    yy += h[i] * x[2 * i + 1];
    pb += h[i] * p[i];
  }
  y = Eigen::Vector2d(yx, yy);
  pbar = pb;
}

void ArcPrecompCheck::batch_outputs(std::size_t head, std::array<Eigen::Vector2d, kBatch>& y,
                                    std::array<double, kBatch>& pbar) const {
  std::array<double, 2 * kBatch> xy;
  if (use_avx2_)
    batch_sums_avx2(h_.data(), h_.size(), ring_[head].data(), ring_p_.data() + head, xy.data(),
                    pbar.data());
  else
    batch_sums_portable(h_.data(), h_.size(), ring_[head].data(), ring_p_.data() + head, xy.data(),
                        pbar.data());
  for (std::size_t j = 0; j < kBatch; ++j) y[j] = Eigen::Vector2d(xy[2 * j], xy[2 * j + 1]);
}

double ArcPrecompCheck::path_distance(const Eigen::Vector2d& y) const {
  // The line before: (p, 0) for p <= 0; from rest, only the start point (the path before a
  // stop at the arc's start may turn there).
  double d = y.x() <= 0.0 && !rest_start_ ? std::abs(y.y()) : y.norm();
  // The arc, centre (0, r), from the origin counter-clockwise through lp_/r_ (whole turns and
  // more: every angle).
  const double th = lp_ / r_, rho = std::hypot(y.x(), y.y() - r_);
  double at = std::atan2(y.y() - r_, y.x()) + 0.5 * std::numbers::pi;  // 0 at the start
  if (at < 0.0) at += 2.0 * std::numbers::pi;
  if (at <= th) d = std::min(d, std::abs(rho - r_));
  // The line after, from the end point along the end's direction; stopping there, only the end
  // point.
  const Eigen::Vector2d e(end_sin_r_, end_1mcos_r_), u(end_cos_, end_sin_);
  const Eigen::Vector2d w = y - e;
  const double along = w.dot(u);
  d = std::min(d, along >= 0.0 && !stops_ ? std::abs(w.x() * u.y() - w.y() * u.x()) : w.norm());
  return d;
}

void ArcPrecompCheck::judge(SimState& s, const Eigen::Vector2d& y, double pbar) const {
  if (judging_ == Judging::Private) {
    const double d = path_distance(y);
    if (d > s.worst) {
      s.worst = d;
      s.worst2 = d * d;
      if (over(d)) stopped_ = true;
    }
    return;
  }
  // The square first: sqrt is monotone, so only a square above the worst's can give a
  // distance above it (the same worst, bit for bit, as comparing every distance).
  const double d2 = (y - point(pbar)).squaredNorm();
  if (!(d2 > s.worst2)) return;
  s.worst2 = d2;
  const double d = std::sqrt(d2);
  if (d > s.worst) {
    s.worst = d;
    if (over(d)) stopped_ = true;
  }
}

void ArcPrecompCheck::flush(SimState& s) const {
  if (s.pending == 0) return;
  // The pending outputs' windows end at slots head + pending − 1 (the oldest) .. head; judged
  // oldest first, as they came.
  std::array<Eigen::Vector2d, kBatch> y;
  std::array<double, kBatch> pbar;
  batch_outputs(s.head, y, pbar);
  for (std::size_t j = s.pending; j-- > 0;) judge(s, y[j], pbar[j]);
  s.pending = 0;
}

void ArcPrecompCheck::advance(SimState& s) const {
  if (s.rest > 0) {
    --s.rest;
    return;
  }
  if (s.v < v_) {  // the interpolator's ramp from rest (next_speed: held at the end rows)
    s.v = rule_.next_speed(s.v, v_, dv_, kNoLimit, (lp_ - s.p) / q_);
    s.p += q_ * s.v * period_s_;
    return;
  }
  s.p += dp_;  // a sample at speed v
}

void ArcPrecompCheck::push_sample(SimState& s) const {
  const std::size_t n = h_.size();
  Eigen::Vector2d x;
  if (s.p > 0.0 && s.p < lp_) {  // point(p) and the radial direction from one sine and cosine
    const double sn = std::sin(s.p / r_), cs = std::cos(s.p / r_);
    x = Eigen::Vector2d(r_ * sn, r_ - r_ * cs);
    // The interpolator's apply_arc_comp: the sample's advances from the start and to the end
    // (the arc's speed ramped towards v_, at most v_p).
    const double advance = q_ * s.v * period_s_;  // in-plane
    if (s.since_first < 0) {
      s.since_first = 0;
      s.phase_in = s.p / advance;
    } else {
      ++s.since_first;
    }
    const double to_end = rule_.advances_to_end((lp_ - s.p) / q_, s.v, v_, dv_, vplan_);
    const ArcCompensation::Offset off = rule_.offset(
        r_, advance / r_, s.since_first + s.phase_in, to_end, rows_,
        ArcCompensation::blend(s.p / q_, len_, blend_), stops_, distance_rows(), distance_rows());
    x += off.radial_mm * Eigen::Vector2d(sn, -cs) + off.along_mm * Eigen::Vector2d(cs, sn);
  } else {
    x = point(s.p);
  }
  put(s.head, x, s.p);  // h_0 on it
  if (++s.count < n) return;
  // A window wholly on the line before the arc (p nondecreasing, so every p_i <= 0, with
  // weights >= 0 also p̄ <= 0): x_i = (p_i, 0), y = (Σ h_i p_i, 0) by the same operations as
  // p̄, and x(p̄) = (p̄, 0): the distance is exactly 0.
  const bool needed = !(s.p <= 0.0 && nonnegative_);
  // Outputs wait to be computed kBatch at a time (flush: the last ones). After a pending one,
  // an output is judged too even where it is not needed: its distance is then exactly 0
  // (above), which changes nothing.
  if (s.pending == 0 && !needed) return;
  if (++s.pending == kBatch) flush(s);
}

double ArcPrecompCheck::run_segment(double p_from, double p_to, double phase, Start start,
                                    End end) const {
  const std::size_t n = h_.size();
  SimState s;
  // From rest: n samples at the arc's start, then the interpolator's ramp from 0 to v.
  s.p = start == Start::FromRest ? 0.0 : p_from - static_cast<double>(n) * dp_ + phase * dp_;
  s.v = start == Start::FromRest ? 0.0 : v_;
  s.rest = start == Start::FromRest ? n : 0;
  const bool stop = end == End::Stop, both = end == End::Both;
  stops_ = stop;  // the end rows for a stop (push_sample)
  rest_start_ = start == Start::FromRest;
  std::size_t at_end = 0;
  SimState fork;
  bool forked = false;
  while (s.p <= p_to && at_end < n && !stopped_) {
    advance(s);
    // The runs part where the end rows first reach a sample (they differ for a stop) or where
    // the command reaches the end: the moving one goes on first.
    if (both && !forked &&
        (s.p >= lp_ ||
         rule_.advances_to_end((lp_ - s.p) / q_, s.v, v_, dv_, vplan_) < ArcEndRows::kSpan)) {
      fork = s;
      std::copy(ring_.begin(), ring_.end(), fork_ring_.begin());
      std::copy(ring_p_.begin(), ring_p_.end(), fork_ring_p_.begin());
      forked = true;
    }
    if (stop && s.p >= lp_) {  // the interpolator stops on the arc's end point
      s.p = lp_;
      ++at_end;
    }
    push_sample(s);
    // Moving on: once the window's oldest sample is past the arc's end, every window from here
    // holds points of the line after it (no offset there), whose output lies on that line
    // to the rounding (~1e-16·r): nothing the transitions left can be larger there.
    if (!stop && s.count >= n && ring_p_[s.head + n - 1] >= lp_) break;
  }
  flush(s);
  if (!forked || stopped_) return s.worst;
  // The stopping run, from the sample where the runs parted.
  const double moving = s.worst;
  s = fork;
  std::swap(ring_, fork_ring_);
  std::swap(ring_p_, fork_ring_p_);
  stops_ = true;
  at_end = 0;
  do {
    if (s.p >= lp_) {
      s.p = lp_;
      ++at_end;
    }
    push_sample(s);
    if (at_end >= n || stopped_) break;
    advance(s);
  } while (s.p <= p_to);
  flush(s);
  return std::max(moving, s.worst);
}

void ArcPrecompCheck::set_arc(double radius_mm, double sweep_abs_rad, double length_mm,
                              double v_plan, double v) const {
  r_ = radius_mm;
  len_ = length_mm;
  lp_ = radius_mm * sweep_abs_rad;
  q_ = lp_ / length_mm;
  const double th = lp_ / r_;
  end_sin_ = std::sin(th);
  end_cos_ = std::cos(th);
  end_sin_r_ = r_ * end_sin_;
  end_1mcos_r_ = r_ - r_ * end_cos_;
  v_ = v;
  vplan_ = v_plan;
  dv_ = rule_.speed_step_mm_s(v_plan);
  blend_ = rule_.blend_length_mm(length_mm, v_plan);
  rows_ = rule_.rows_weight(length_mm, v_plan);
  end_len_ = rule_.end_length_mm(length_mm, v_plan);
  dp_ = q_ * v * period_s_;
}

double ArcPrecompCheck::isolated_runs(double v, double phase, bool paired) const {
  const double W = static_cast<double>(h_.size()) * dp_, lb = q_ * end_len_;
  // Between moving tangent lines, from rest at its start, to rest at its end.
  if (lp_ <= 2.0 * (lb + 2.0 * W)) {
    if (paired) {
      const double a = run_segment(-W, lp_ + 2.0 * W, phase, Start::Moving, End::Both);
      if (stopped_) return a;
      return std::max(a, run_segment(0.0, lp_ + 2.0 * W, phase, Start::FromRest, End::Both));
    }
    return std::max({run_segment(-W, lp_ + 2.0 * W, phase, Start::Moving, End::Moving),
                     run_segment(0.0, lp_ + 2.0 * W, phase, Start::FromRest, End::Stop),
                     run_segment(0.0, lp_ + 2.0 * W, phase, Start::FromRest, End::Moving),
                     run_segment(-W, lp_ + 2.0 * W, phase, Start::Moving, End::Stop)});
  }
  const double start_moving = run_segment(-W, lb + 2.0 * W, phase, Start::Moving, End::Moving);
  if (stopped_) return start_moving;
  const double from_rest =
      run_segment(0.0, lb + 2.0 * W + v * static_cast<double>(h_.size()) * q_ * period_s_, phase,
                  Start::FromRest, End::Moving);
  if (stopped_) return std::max(start_moving, from_rest);
  if (paired)
    return std::max({start_moving, from_rest,
                     run_segment(lp_ - lb - W, lp_ + 2.0 * W, phase, Start::Moving, End::Both)});
  return std::max({start_moving, from_rest,
                   run_segment(lp_ - lb - W, lp_ + 2.0 * W, phase, Start::Moving, End::Moving),
                   run_segment(lp_ - lb - W, lp_ + 2.0 * W, phase, Start::Moving, End::Stop)});
}

double ArcPrecompCheck::run_stepped(double p_start, double p_until, Start start, bool stop) const {
  // The interpolator's loop (Interpolator::step_n) on the isolated path, in-plane: a sample
  // spends T on the line before at vline_, then on the arc at comp_ramped_speed (the previous
  // sample's speed ± dv_, at most vplan_), then on the line after at vline_ (or holds on the
  // end point); the correction and end rows are the arc's at the speed of the sample's last
  // motion.
  const std::size_t n = h_.size();
  const double T = period_s_, eps = 1e-9 * T;
  stops_ = stop;
  SimState s;
  int seg = start == Start::FromRest ? 1 : (p_start < 0.0 ? 0 : 1);
  double sa = seg == 1 && start != Start::FromRest ? p_start / q_ : 0.0;  // path on the arc
  s.p = start == Start::FromRest ? 0.0 : p_start;
  s.v = start == Start::FromRest ? 0.0 : (seg == 0 ? vline_ : v_);  // the last sample's speed
  s.rest = start == Start::FromRest ? n : 0;
  std::size_t at_end = 0;
  while (!stopped_) {
    if (s.rest > 0) {
      --s.rest;
    } else {
      double dt = T, speed = s.v;
      // Along a line piece at speed w up to in-plane `end`: true once it is reached.
      auto along = [&](double w, double end) {
        const double left = (end - s.p) / q_;
        speed = w;
        if (w * dt < left) {
          s.p += q_ * w * dt;
          dt = 0.0;
          return false;
        }
        dt = std::max(0.0, dt - left / w);
        s.p = end;
        return true;
      };
      while (dt > eps) {
        if (seg == 0) {  // the line before: at vline_, its last near_p_ at v_
          const bool far = s.p < -near_p_;
          if (along(far ? vline_ : v_, far ? -near_p_ : 0.0) && !far) seg = 1;
        } else if (seg == 1) {
          const double v = rule_.next_speed(s.v, v_, dv_, vplan_, len_ - sa);
          const double left = len_ - sa;
          speed = v;
          if (v * dt < left) {
            sa += v * dt;
            s.p = q_ * sa;
            dt = 0.0;
          } else {
            dt = std::max(0.0, dt - left / v);
            sa = len_;
            s.p = lp_;
            seg = 2;
            if (stop) break;  // the rest of the sample is dropped: the filter drains
          }
        } else {  // the line after: its first near_p_ at v_, then at vline_
          if (stop) break;
          const bool near = s.p < lp_ + near_p_;
          along(near ? v_ : vline_, near ? lp_ + near_p_ : kNoLimit);
        }
      }
      s.v = speed;
    }
    if (seg == 2 && stop) ++at_end;
    push_sample(s);
    if (stop ? at_end >= n : (s.count >= n && ring_p_[s.head + n - 1] >= lp_)) break;
    if (s.p > p_until) break;
  }
  flush(s);
  return s.worst;
}

double ArcPrecompCheck::stepped_runs(double phase) const {
  const std::size_t n = h_.size();
  const double W = static_cast<double>(n) * dp_, lb = q_ * end_len_, inf = kNoLimit;
  // A window on the line before, its first sample `phase` of a sample along.
  const double before = -near_p_ - (static_cast<double>(n) - phase) * q_ * vline_ * period_s_;
  if (lp_ <= 2.0 * (lb + 2.0 * W)) {  // short: each run crosses the whole arc
    double worst = run_stepped(before, inf, Start::Moving, false);
    if (!stopped_) worst = std::max(worst, run_stepped(before, inf, Start::Moving, true));
    if (!stopped_) worst = std::max(worst, run_stepped(0.0, inf, Start::FromRest, false));
    return worst;
  }
  // Long: the entry (on the arc past the blend and two windows) and the exit from the steady
  // arc; the stop at the end and the start from rest are isolated_mm's (no line beside).
  double worst = run_stepped(before, lb + 2.0 * W, Start::Moving, false);
  if (!stopped_)
    worst = std::max(worst, run_stepped(lp_ - lb - 2.0 * W, inf, Start::Moving, false));
  return worst;
}

double ArcPrecompCheck::stepped_mm(double radius_mm, double sweep_abs_rad, double length_mm,
                                   double v_plan, double v, double v_line, double phase) const {
  set_arc(radius_mm, sweep_abs_rad, length_mm, v_plan, v);
  vline_ = v_line;
  near_p_ = q_ * near_s_ * v_plan;
  return stepped_runs(phase);
}

double ArcPrecompCheck::isolated_mm(double radius_mm, double sweep_abs_rad, double length_mm,
                                    double v_plan, double v, double phase) const {
  set_arc(radius_mm, sweep_abs_rad, length_mm, v_plan, v);
  return isolated_runs(v, phase, true);
}

double ArcPrecompCheck::isolated_unpaired_mm(double radius_mm, double sweep_abs_rad,
                                             double length_mm, double v_plan, double v,
                                             double phase) const {
  set_arc(radius_mm, sweep_abs_rad, length_mm, v_plan, v);
  return isolated_runs(v, phase, false);
}
double ArcPrecompCheck::ramp_mm(double radius_mm, double sweep_abs_rad, double length_mm,
                                double v_plan) const {
  return ramp_to_mm(radius_mm, sweep_abs_rad, length_mm, v_plan, 0.0);
}

double ArcPrecompCheck::ramps_mm(double radius_mm, double sweep_abs_rad, double length_mm,
                                 double v_plan) const {
  double worst = 0.0;
  for (double f : kRampFloors)
    worst = std::max({worst, ramp_to_mm(radius_mm, sweep_abs_rad, length_mm, v_plan, f),
                      reversals_mm(radius_mm, sweep_abs_rad, length_mm, v_plan, f)});
  return worst;
}

template <class Profile>
double ArcPrecompCheck::steady_arc_mm(double radius_mm, double sweep_abs_rad, double length_mm,
                                      double v_start, Profile next_speed) const {
  const std::size_t n = h_.size();
  const double q = radius_mm * sweep_abs_rad / length_mm, r = radius_mm;
  const auto on_circle = [r](double p, double rad) {
    return Eigen::Vector2d(rad * std::sin(p / r), r - rad * std::cos(p / r));
  };
  double v = v_start, p = 0.0, worst = 0.0;
  std::size_t count = 0, head = 0;
  for (std::size_t k = 0; next_speed(k, v); ++k) {
    p += q * v * period_s_;
    put(head, on_circle(p, r + rule_.correction_mm(r, v * sweep_abs_rad / length_mm)), p);
    if (++count < n) continue;
    Eigen::Vector2d y;
    double pbar;
    window_output(head, y, pbar);
    worst =
        std::max(worst, judging_ == Judging::Private ? std::abs(std::hypot(y.x(), y.y() - r) - r)
                                                     : (y - on_circle(pbar, r)).norm());
  }
  return worst;
}

double ArcPrecompCheck::reversals_mm(double radius_mm, double sweep_abs_rad, double length_mm,
                                     double v_plan, double floor) const {
  // v_p for a window, then down to floor·v_p, up to v_p, down and up again, each turning at
  // once (the speed's step reverses: twice the ramp's change of acceleration), then a window
  // at v_p.
  const std::size_t n = h_.size();
  const double dv = rule_.speed_step_mm_s(v_plan), low = floor * v_plan;
  const std::array<double, 4> targets{low, v_plan, low, v_plan};
  std::size_t leg = 0, after = 0;
  return steady_arc_mm(radius_mm, sweep_abs_rad, length_mm, v_plan, [&](std::size_t k, double& v) {
    if (after > n) return false;
    if (k >= n && leg < targets.size()) {
      const double t = targets[leg];
      v = t < v ? std::max(t, v - dv) : std::min(t, v + dv);
      if (v == t) ++leg;
    } else if (leg == targets.size()) {
      ++after;
    }
    return true;
  });
}

double ArcPrecompCheck::ramp_to_mm(double radius_mm, double sweep_abs_rad, double length_mm,
                                   double v_plan, double floor) const {
  // v_p for a window, down to floor·v_p, a window there, up to v_p, a window at v_p.
  const int n = static_cast<int>(h_.size());
  const double dv = rule_.speed_step_mm_s(v_plan), low = floor * v_plan;
  const int ramp = rule_.ramp_samples();
  const int total = 3 * n + 2 * ramp + 2;
  return steady_arc_mm(radius_mm, sweep_abs_rad, length_mm, v_plan, [&](std::size_t k, double& v) {
    if (!(static_cast<int>(k) < total)) return false;
    const int t = static_cast<int>(k) - n;
    if (t >= 0 && t <= ramp)
      v = std::max(low, v - dv);
    else if (t > ramp + n)
      v = std::min(v_plan, v + dv);
    return true;
  });
}

double ArcPrecompCheck::isolated_worst_mm(double radius_mm, double sweep_abs_rad, double length_mm,
                                          double v_plan) const {
  double worst = 0.0;
  for (double f : {1.0, 0.6}) {
    worst =
        std::max(worst, isolated_mm(radius_mm, sweep_abs_rad, length_mm, v_plan, f * v_plan, 0.25));
    if (line_ratio_ > 0.0)  // the lines beside at up to line_ratio·v_p: the steps at the ends
      worst = std::max(worst, stepped_mm(radius_mm, sweep_abs_rad, length_mm, v_plan, f * v_plan,
                                         f * line_ratio_ * v_plan, 0.25));
  }
  return worst;
}

double ArcPrecompCheck::error_mm(double radius_mm, double sweep_abs_rad, double length_mm,
                                 double v_plan) const {
  return isolated_worst_mm(radius_mm, sweep_abs_rad, length_mm, v_plan) +
         ramp_mm(radius_mm, sweep_abs_rad, length_mm, v_plan);
}

bool ArcPrecompCheck::error_within(double radius_mm, double sweep_abs_rad, double length_mm,
                                   double v_plan, double scale, double share) const {
  Cached& e = cache_[cache_slot(radius_mm, sweep_abs_rad, length_mm, v_plan)];
  const bool hit = e.r == radius_mm && e.sweep == sweep_abs_rad && e.len == length_mm &&
                   e.v == v_plan && e.judging == judging_;
  // error_mm = max(0, isolated at v_p, at 0.6·v_p) + ramp; every partial maximum is a lower
  // bound of it, and (x + ramp)·scale grows with x in floating point too.
  if (hit && (e.exact || (e.iso + e.ramp) * scale > share))
    return (e.iso + e.ramp) * scale <= share;
  const double ramp = hit ? e.ramp : ramp_mm(radius_mm, sweep_abs_rad, length_mm, v_plan);
  stop_add_ = ramp;
  stop_scale_ = scale;
  stop_share_ = share;
  stopped_ = false;
  double worst = 0.0;
  for (double f : {1.0, 0.6}) {
    worst =
        std::max(worst, isolated_mm(radius_mm, sweep_abs_rad, length_mm, v_plan, f * v_plan, 0.25));
    if (stopped_) break;
    if (line_ratio_ > 0.0)
      worst = std::max(worst, stepped_mm(radius_mm, sweep_abs_rad, length_mm, v_plan, f * v_plan,
                                         f * line_ratio_ * v_plan, 0.25));
    if (stopped_) break;
  }
  const bool exact = !stopped_;
  stop_add_ = 0.0;
  stop_scale_ = 1.0;
  stop_share_ = std::numeric_limits<double>::infinity();
  stopped_ = false;
  e = Cached{radius_mm, sweep_abs_rad, length_mm, v_plan, ramp, worst, exact, judging_};
  return exact && (worst + ramp) * scale <= share;
}

}  // namespace gm
