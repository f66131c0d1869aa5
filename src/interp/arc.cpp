// Arc centre and tolerance rules of LinuxCNC, grbl and g2core (numbers cited from their sources).
#include "interp/arc.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gm {

namespace {

// LinuxCNC interp_internal.hh: CENTER_ARC_RADIUS_TOLERANCE_{INCH,MM} = 2*0.001*sqrt2 in,
// 2*0.01*sqrt2 mm; RADIUS_TOLERANCE_INCH = 0.00005 in, RADIUS_TOLERANCE_MM = 0.00005*25.4 mm;
// SPIRAL_RELATIVE_TOLERANCE = 0.001. All in program units.
constexpr double kLcncSpiralTolInch = 2 * 0.001 * std::numbers::sqrt2;
constexpr double kLcncSpiralTolMm = 2 * 0.01 * std::numbers::sqrt2;
constexpr double kLcncRadiusTolInch = 0.00005;
constexpr double kLcncRadiusTolMm = 0.00005 * 25.4;
constexpr double kLcncSpiralRel = 0.001;
// grbl gcode.c (mm): fail if dr > 0.005 and (dr > 0.5 or dr > 0.001 r).
constexpr double kGrblMinMm = 0.005, kGrblMaxMm = 0.5, kGrblRel = 0.001;
// g2core plan_arc.h (mm): ARC_RADIUS_ERROR_MAX 1.0, ARC_RADIUS_ERROR_MIN 0.005, TOLERANCE 0.001.
constexpr double kG2MinMm = 0.005, kG2MaxMm = 1.0, kG2Rel = 0.001;

// An R-form arc: its centre on the perpendicular bisector of the chord, or the error when R
// cannot reach the end point.
ArcResult r_form_arc(const ArcInput& in, double radius_tol, const char* unit) {
  ArcResult res;
  if (in.end_a == in.start_a && in.end_b == in.start_b) {
    res.error = ErrorCode::ArcRSameEndPoint;
    res.message = "R-form arc ends where it starts; a full circle needs I/J/K";
    return res;
  }
  const double abs_r = std::fabs(in.r);
  const double mid_a = (in.end_a + in.start_a) / 2.0, mid_b = (in.end_b + in.start_b) / 2.0;
  double half = std::hypot(mid_a - in.end_a, mid_b - in.end_b);
  bool too_small = false;
  if (in.rule == ArcRule::LinuxCnc) {
    too_small = half - abs_r > radius_tol;
  } else {
    // grbl and g2core: only when 4r^2 < d^2 (no slack), compared in mm.
    too_small = abs_r < half;
  }
  if (too_small || abs_r == 0.0) {
    res.error = ErrorCode::ArcRadiusTooSmall;
    res.message = fmt::format(
        "arc radius too small to reach the end point: |R| = {:.6g} {}, half the chord = {:.6g} "
        "{} "
        "(short by {:.6g} {})",
        abs_r, unit, half, unit, half - abs_r, unit);
    return res;
  }
  if (half > abs_r) half = abs_r;  // within tolerance: a semicircle
  // Centre on the perpendicular bisector; left of the chord for a short CCW arc (LinuxCNC).
  const double chord_angle = std::atan2(in.end_b - in.start_b, in.end_a - in.start_a);
  const bool right = (!in.ccw && in.r > 0) || (in.ccw && in.r < 0);
  const double theta =
      right ? chord_angle - std::numbers::pi / 2 : chord_angle + std::numbers::pi / 2;
  const double offset = std::sqrt(std::max(0.0, abs_r * abs_r - half * half));
  res.center_a = mid_a + offset * std::cos(theta);
  res.center_b = mid_b + offset * std::sin(theta);
  res.rel_a = res.center_a - in.start_a;
  res.rel_b = res.center_b - in.start_b;
  return res;
}

// True when the radii to the start (r1) and to the end (r2) differ beyond the dialect's rule.
bool radii_differ(const ArcInput& in, double r1, double r2) {
  const bool inch = in.mm_per_unit != 1.0;
  const double abs_err = std::fabs(r1 - r2);
  const double rel_err = abs_err / std::max(r1, r2);
  switch (in.rule) {
    case ArcRule::LinuxCnc: {
      const double tol = inch ? kLcncSpiralTolInch : kLcncSpiralTolMm;
      return abs_err > 100.0 * tol || (abs_err > tol && rel_err > kLcncSpiralRel);
    }
    case ArcRule::Grbl: {
      const double dr_mm = abs_err * in.mm_per_unit, r_mm = r1 * in.mm_per_unit;
      return dr_mm > kGrblMinMm && (dr_mm > kGrblMaxMm || dr_mm > kGrblRel * r_mm);
    }
    case ArcRule::G2core: {
      const double dr_mm = abs_err * in.mm_per_unit, r_mm = r1 * in.mm_per_unit;
      return dr_mm > kG2MaxMm || (dr_mm > kG2MinMm && dr_mm > kG2Rel * r_mm);
    }
  }
  return false;
}

// The message for radii_differ. The rule's text only when it is needed (formatting it for
// every arc cost 12 % of a check).
std::string radius_mismatch_message(const ArcInput& in, double r1, double r2, const char* unit) {
  const bool inch = in.mm_per_unit != 1.0;
  const double abs_err = std::fabs(r1 - r2);
  const double rel_err = abs_err / std::max(r1, r2);
  std::string rule_text;
  switch (in.rule) {
    case ArcRule::LinuxCnc: {
      const double tol = inch ? kLcncSpiralTolInch : kLcncSpiralTolMm;
      rule_text = fmt::format("linuxcnc: fails above {:.6g} {}, or above {:.6g} {} and 0.1 %",
                              100.0 * tol, unit, tol, unit);
      break;
    }
    case ArcRule::Grbl:
      rule_text = "grbl: fails above 0.005 mm and (above 0.5 mm or 0.1 % of r1)";
      break;
    case ArcRule::G2core:
      rule_text = "g2core: fails above 1.0 mm, or above 0.005 mm and 0.1 % of r1";
      break;
  }
  return fmt::format(
      "radius to end of arc differs from radius to start: r1 = {:.6g} {}, r2 = {:.6g} {}, "
      "abs_err = {:.4g} {}, rel_err = {:.4f} % ({})",
      r1, unit, r2, unit, abs_err, unit, rel_err * 100.0, rule_text);
}

// True when no rule can refuse the arc whose centre `res` holds: its radii, by square roots of
// their squares, are within a few units in the last place of hypot's when below kFastRadius,
// far closer than the margins here (both radii beyond twice the zero-radius tolerance, differing
// by under half the least difference a rule refuses). The radii by hypot are then not needed:
// the arc passes as it would with them. Otherwise (or for huge and tiny radii) they decide.
bool clearly_within_rules(const ArcInput& in, const ArcResult& res, double radius_tol) {
  constexpr double kFastRadius = 1e6;  // program units: a few ulps here are below 1e-9
  const double a1 = res.center_a - in.start_a, b1 = res.center_b - in.start_b;
  const double a2 = res.center_a - in.end_a, b2 = res.center_b - in.end_b;
  const double s1 = std::sqrt(a1 * a1 + b1 * b1), s2 = std::sqrt(a2 * a2 + b2 * b2);
  const double least_refused = in.rule == ArcRule::LinuxCnc
                                   ? (in.mm_per_unit != 1.0 ? kLcncSpiralTolInch : kLcncSpiralTolMm)
                                   : std::min(kGrblMinMm, kG2MinMm) / in.mm_per_unit;
  return s1 > 2.0 * radius_tol && s2 > 2.0 * radius_tol && s1 < kFastRadius && s2 < kFastRadius &&
         std::fabs(s1 - s2) < 0.5 * least_refused;
}

}  // namespace

ArcResult compute_arc(const ArcInput& in) {
  const bool inch = in.mm_per_unit != 1.0;
  const double radius_tol = inch ? kLcncRadiusTolInch : kLcncRadiusTolMm;
  const char* unit = inch ? "in" : "mm";
  if (in.use_r) return r_form_arc(in, radius_tol, unit);

  ArcResult res;
  if (in.offsets_absolute) {
    res.center_a = in.off_a;
    res.center_b = in.off_b;
    res.rel_a = in.off_a - in.start_a;
    res.rel_b = in.off_b - in.start_b;
  } else {
    res.center_a = in.start_a + in.off_a;
    res.center_b = in.start_b + in.off_b;
    res.rel_a = in.off_a;
    res.rel_b = in.off_b;
  }
  if (clearly_within_rules(in, res, radius_tol)) return res;
  const double r1 = std::hypot(res.center_a - in.start_a, res.center_b - in.start_b);
  const double r2 = std::hypot(res.center_a - in.end_a, res.center_b - in.end_b);
  if (r1 < radius_tol || r2 < radius_tol) {
    res.error = ErrorCode::ArcZeroRadius;
    res.message = fmt::format("zero radius arc: r1 = {:.6g} {}, r2 = {:.6g} {} (minimum {:.6g} {})",
                              r1, unit, r2, unit, radius_tol, unit);
    return res;
  }
  if (radii_differ(in, r1, r2)) {
    res.error = ErrorCode::ArcRadiusMismatch;
    res.message = radius_mismatch_message(in, r1, r2, unit);
  }
  return res;
}

}  // namespace gm
