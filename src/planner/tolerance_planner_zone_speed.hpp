// TolerancePlanner's bisections of a speed over the zones it opens (the templates the corners'
// and the arcs' decisions share), and the float steps they solve the zone tests with.
#pragma once

#include "planner/tolerance_planner.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

namespace gm {
namespace zone_speed {

/// The next float up and down (finite x): a step of the bit pattern, as std::nextafter.
inline double float_up(double x) {
  if (x == 0.0) return std::numeric_limits<double>::denorm_min();
  const auto b = std::bit_cast<std::int64_t>(x);
  return std::bit_cast<double>(x > 0.0 ? b + 1 : b - 1);
}
inline double float_down(double x) {
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
inline double first_joining_speed(double s0, double s1, double t, const double* b_s1,
                                  const double* a_s0) {
  const double nan = std::nan("");
  if (!(t > 0.0)) return nan;
  auto speed_for = [t](double u) {  // the smallest v with v·t >= u
    if (!(u >= 0.0)) return 0.0;
    return first_true_near(u / t, [&](double v) { return v * t >= u; });
  };
  double v = std::numeric_limits<double>::infinity();
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

}  // namespace zone_speed

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
    if (const double v = zone_speed::first_joining_speed(s0, s1, t, before ? &before->s1 : nullptr,
                                                         after ? &after->s0 : nullptr);
        v > below && v <= above && joins(v) && !joins(zone_speed::float_down(v))) {
      below = zone_speed::float_down(v);
      above = v;
    }
    for (int it = 0; it < 40 && zone_speed::float_up(below) < above; ++it) {
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

}  // namespace gm
