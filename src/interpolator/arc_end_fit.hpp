// A pre-compensated arc's ends in two directions: offsets on the arc's first and last samples,
// radial and tangential, fitted for the speeds the arc runs at so that the Acc/Dec output stays
// nearest the path or the path's point at the window's mean (docs/tolerance-arc-ends.md).
#pragma once

#include <limits>
#include <vector>

namespace gm {

/// An arc run sample by sample, in the arc's own frame: a line along +x into a counter-clockwise
/// arc of radius r from the origin (centre (0, r)) through `sweep_rad` (infinity: an arc that
/// never ends), then the tangent line. speed_mm_s[i] is sample i's path advance over the period;
/// sample `first` is the arc's first and lies `phase` (0..1] of its advance past the arc's start.
/// `planned_mm_s` is the arc's planned speed: its steady loss is the unit of worst_fraction.
struct ArcRun {
  double radius_mm = 1.0;
  double sweep_rad = std::numeric_limits<double>::infinity();
  std::vector<double> speed_mm_s;
  int first = 0;
  double phase = 0.25;
  double planned_mm_s = 0.0;

  /// A constant speed v: two windows of line, the arc, four windows after it (`window` samples).
  static ArcRun constant(double radius_mm, double sweep_rad, double v_mm_s, double period_s,
                         double phase, int window);
};

/// The command's offset from the path on each sample of an ArcRun, in mm: along the outward
/// normal (radial) and along the motion (along). Zero off the arc.
struct ArcOffsets {
  std::vector<double> radial_mm, along_mm;
};

/// A command linear in unknowns u: the offsets base + Σ_q u_q·columns[q] on a run's samples.
struct ArcCommandModel {
  ArcOffsets base;
  std::vector<ArcOffsets> columns;
};

/// One sample of a run as the rules see it: on the arc or not, its path position from the arc's
/// start, its advance over the period, its steady correction c and its rate x = advance / r.
struct ArcSample {
  bool on = false;
  double s_mm = 0.0, advance_mm = 0.0, c_mm = 0.0, x = 0.0;
};

/// What the worst of an output is measured by: the distance of the output y from the path (the
/// contour error), or |y − x(s̄)|, its distance from the path's point at the window's mean
/// position s̄ (what adds up over a path's elements: the tolerance planner's measure).
enum class ArcEndMeasure { Distance, FromMean };

/// The Acc/Dec output of an arc's command, for a filter (weights h_i, Σ = 1) at period
/// T: measured against the path (the line before, the arc, the line after), and fitted.
class ArcEndFit {
 public:
  static constexpr int kMaxUnknowns = 16;

  ArcEndFit(std::vector<double> weights, double period_s);

  /// The unknowns u (at most kMaxUnknowns) of `models` (one per run, the same unknowns in each)
  /// minimising M_p(u)² + μ·c²·|u|² over all the runs' outputs at once: M_p the power mean of
  /// |y − x(s̄)| over every sample whose window is full, c the first run's steady correction at
  /// its planned speed (columns in units of it weigh |u| as multiples of c), p raised from 2 to
  /// 128 (M_p then within a factor N^(1/128) of the worst of N samples), Newton steps with a
  /// line search at each p from the last p's optimum. The problem is convex (y is linear in u):
  /// the result is its optimum whatever the path to it.
  /// With `measure` Distance: the distance from the path in place of |y − x(s̄)|, linearised
  /// around the unknowns and minimised again kDistancePasses times (the passes' best kept).
  std::vector<double> fit_shared(const std::vector<ArcRun>& runs,
                                 const std::vector<ArcCommandModel>& models, double mu,
                                 ArcEndMeasure measure = ArcEndMeasure::FromMean) const;
  static constexpr int kDistancePasses = 8;
  /// The run's samples.
  std::vector<ArcSample> samples(const ArcRun& run) const;
  /// The radial blend: c blended in (out) linearly over the arc's first (last)
  /// min(L/2, 2·T·v_planned) of path, no tangential part.
  ArcOffsets linear_blend(const ArcRun& run) const;
  /// The worst `measure` of the output, every sample whose window is full, over the steady
  /// loss r(1 − A) at the planned speed.
  double worst_fraction(const ArcRun& run, const ArcOffsets& offsets,
                        ArcEndMeasure measure = ArcEndMeasure::Distance) const;
  /// A(x) = Σ h_i cos((i − m)·x); |Σ h_i e^{−j·i·x}| for weights that are not symmetric.
  double gain(double x) const;

 private:
  struct Samples;  // the run's path positions, frames, steady corrections and filtered positions
  /// `means`: also the windows' mean positions s̄ (O(samples × weights)).
  Samples prepare(const ArcRun& run, bool means = true) const;

  std::vector<double> h_;
  double period_s_;
  double centre_ = 0.0;
  bool symmetric_ = true;  ///< about the centre of the weights' support
};

}  // namespace gm
