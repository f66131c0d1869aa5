// CornerMomentGrid: FilterMoments' corner-moment bisection with comparisons decided by running
// sums.
#include "planner/corner_moment_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gm {

CornerMomentGrid::CornerMomentGrid(const FilterMoments& filter) : f_(filter) {
  const std::vector<double>& h = f_.h_;
  const std::size_t n = h.size();
  const double T = f_.period_s_;
  signed_ = f_.over_s_ > 0.0 || f_.under_s_ > 0.0;
  // A reference sum of m terms rounds each term at most twice (relative 2u) and adds them left to
  // right (γ_{m−1} of the sum of |terms|); the running sums here add them in another order (γ_m),
  // then add once or twice more. (2m + 6)·u = (m + 3)·ε of the sum of |terms| bounds the two
  // apart; (m + 8)·ε·1.01, plus an absolute floor, leaves room for rounding the bound itself.
  if (!signed_) {
    c_.resize(n);
    for (std::size_t i = 0; i < n; ++i) c_[i] = static_cast<double>(i) * T;
    suf_h_.assign(n + 1, 0.0), suf_hc_.assign(n + 1, 0.0);
    suf_abs_h_.assign(n + 1, 0.0), suf_abs_hc_.assign(n + 1, 0.0);
    for (std::size_t i = n; i-- > 0;) {
      suf_h_[i] = suf_h_[i + 1] + h[i];
      suf_hc_[i] = suf_hc_[i + 1] + h[i] * c_[i];
      suf_abs_h_[i] = suf_abs_h_[i + 1] + std::abs(h[i]);
      suf_abs_hc_[i] = suf_abs_hc_[i + 1] + std::abs(h[i]) * c_[i];
    }
    pre_h_.assign(n + 1, 0.0), pre_hc_.assign(n + 1, 0.0);
    pre_abs_h_.assign(n + 1, 0.0), pre_abs_hc_.assign(n + 1, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      pre_h_[i + 1] = pre_h_[i] + h[i];
      pre_hc_[i + 1] = pre_hc_[i] + h[i] * c_[i];
      pre_abs_h_[i + 1] = pre_abs_h_[i] + std::abs(h[i]);
      pre_abs_hc_[i + 1] = pre_abs_hc_[i] + std::abs(h[i]) * c_[i];
    }
  } else {
    // The intervals, weights and whole-interval terms exactly as pre_pos and post_pos form them.
    a_lo_.resize(n), a_hi_.resize(n), a_c_.resize(n), a_suf_.assign(n + 1, 0.0);
    double c = 1.0;
    for (std::size_t k = 0; k < n; ++k) {
      a_hi_[k] = static_cast<double>(k) * T;
      a_lo_[k] = a_hi_[k] - T;
      a_c_[k] = std::max(c, 0.0);
      c -= h[k];
    }
    for (std::size_t k = n; k-- > 0;)
      a_suf_[k] = a_suf_[k + 1] + a_c_[k] * std::clamp(a_hi_[k] - a_lo_[k], 0.0, T);
    b_lo_.resize(n), b_hi_.resize(n), b_s_.resize(n), b_pre_.assign(n + 1, 0.0);
    double s = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      s += h[k];
      b_lo_[k] = static_cast<double>(k) * T;
      b_hi_[k] = b_lo_[k] + T;
      b_s_[k] = std::max(s, 0.0);
      b_pre_[k + 1] = b_pre_[k] + b_s_[k] * std::clamp(b_hi_[k] - b_lo_[k], 0.0, T);
    }
  }
  d_.assign(static_cast<std::size_t>(f_.order()) + 1, 0.0);
  known_.assign(d_.size(), 0);
}

double CornerMomentGrid::at(int j) {
  const auto i = static_cast<std::size_t>(j);
  if (!known_[i]) {
    const int k = 2 * j;  // the pause as the table of half samples formed it
    d_[i] = moment_s(0.5 * k * f_.period_s());
    known_[i] = 1;
  }
  return d_[i];
}

double CornerMomentGrid::slack(std::size_t terms) {
  return (static_cast<double>(terms) + 8.0) * std::numeric_limits<double>::epsilon() * 1.01;
}

CornerMomentGrid::Bounded CornerMomentGrid::pre(double t) const {
  constexpr double kFloor = 1e-300;
  if (!signed_) {  // Σ_{c_i > t} h_i·(c_i − t)
    const auto i = static_cast<std::size_t>(std::upper_bound(c_.begin(), c_.end(), t) - c_.begin());
    const double abs_sum = suf_abs_hc_[i] + std::abs(t) * suf_abs_h_[i];
    return {suf_hc_[i] - t * suf_h_[i], slack(c_.size() - i) * abs_sum + kFloor};
  }
  // Intervals ending at or before t add nothing; those starting at or after t add their whole.
  auto k =
      static_cast<std::size_t>(std::upper_bound(a_hi_.begin(), a_hi_.end(), t) - a_hi_.begin());
  const std::size_t terms = a_hi_.size() - k;
  double part = 0.0;
  for (; k < a_hi_.size() && a_lo_[k] < t; ++k)
    part += a_c_[k] * std::clamp(a_hi_[k] - t, 0.0, f_.period_s_);
  const double sum = part + a_suf_[k];
  return {sum, slack(terms) * sum + kFloor};
}

CornerMomentGrid::Bounded CornerMomentGrid::post(double t) const {
  constexpr double kFloor = 1e-300;
  if (!signed_) {  // Σ_{c_i < t} h_i·(t − c_i)
    const auto i = static_cast<std::size_t>(std::lower_bound(c_.begin(), c_.end(), t) - c_.begin());
    const double abs_sum = std::abs(t) * pre_abs_h_[i] + pre_abs_hc_[i];
    return {t * pre_h_[i] - pre_hc_[i], slack(i) * abs_sum + kFloor};
  }
  // All but the last interval: whole before t, partial across it, nothing after it; the last
  // one extends past its end (the step response stays at S_N).
  const std::size_t last = b_lo_.size() - 1;
  auto k = static_cast<std::size_t>(
      std::upper_bound(b_hi_.begin(), b_hi_.begin() + static_cast<std::ptrdiff_t>(last), t) -
      b_hi_.begin());
  double sum = b_pre_[k];
  for (; k < last && b_lo_[k] < t; ++k)
    sum += b_s_[k] * std::clamp(t - b_lo_[k], 0.0, f_.period_s_);
  sum += b_s_[last] * std::max(t - b_lo_[last], 0.0);
  // The same operations in the same order as post_pos (the prefix sums are its partial sums,
  // the terms after the partial ones add +0): the reference's value itself.
  return {sum, 0.0};
}

// The reference's sums, skipping only terms that are exactly zero: a leading zero term leaves the
// sum at +0 and a trailing one leaves it as it is (a sum that starts at +0 never becomes −0).
double CornerMomentGrid::exact_pre(double t) const {
  const std::size_t n = f_.h_.size();
  double a = 0.0;
  if (!signed_) {  // pre_moment: terms with i·T > t
    for (auto i = static_cast<std::size_t>(std::upper_bound(c_.begin(), c_.end(), t) - c_.begin());
         i < n; ++i)
      a += f_.h_[i] * std::max(c_[i] - t, 0.0);
    return a;
  }
  // pre_pos: intervals ending after t
  for (auto k = static_cast<std::size_t>(std::upper_bound(a_hi_.begin(), a_hi_.end(), t) -
                                         a_hi_.begin());
       k < n; ++k)
    a += a_c_[k] * std::clamp(a_hi_[k] - std::max(t, a_lo_[k]), 0.0, f_.period_s_);
  return a;
}

double CornerMomentGrid::exact_post(double t) const {
  if (!signed_) {  // post_moment: terms with i·T < t
    double b = 0.0;
    const auto end =
        static_cast<std::size_t>(std::lower_bound(c_.begin(), c_.end(), t) - c_.begin());
    for (std::size_t i = 0; i < end; ++i) b += f_.h_[i] * std::max(t - c_[i], 0.0);
    return b;
  }
  return post(t).value;  // post_pos: its prefix sums are the reference's own partial sums
}

bool CornerMomentGrid::pre_exceeds(double t, double t_post) const {
  const Bounded a = pre(t), b = post(t_post);
  if (a.value - a.error > b.value + b.error) return true;
  if (a.value + a.error < b.value - b.error) return false;
  return exact_pre(t) > exact_post(t_post);
}

double CornerMomentGrid::moment_s(double pause_s) const {
  // FilterMoments::corner_moment_s, step for step.
  const double period_s = f_.period_s_;
  double lo = -period_s, hi = f_.tau_s() + pause_s + period_s;
  for (int it = 0; it < 200 && hi - lo > 1e-15 * (1.0 + hi); ++it) {
    const double mid = 0.5 * (lo + hi);
    (pre_exceeds(mid, mid - pause_s) ? lo : hi) = mid;
  }
  const double t = 0.5 * (lo + hi);
  const double d = std::max(0.0, std::min(exact_pre(t), exact_post(t - pause_s)));
  return signed_ ? std::max({d, f_.over_s_, f_.under_s_}) : d;
}

}  // namespace gm
