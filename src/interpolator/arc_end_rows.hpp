// A pre-compensated arc's ends in two directions: offsets on the arc's first and last samples,
// radial and tangential, fitted for the speeds the arc runs at so that the Acc/Dec output stays
// nearest the path (docs/tolerance.md, "The arc's ends in two directions, judged by the distance
// to the path").
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

/// Fits and measures the offsets for a symmetric FIR (weights h_i, Σ = 1) at period T. The
/// steady correction c = r(1/A(x) − 1) (x: the sample's advance over r) on the arc, except on its
/// first and last kEndSamples samples, whose offsets are free in both directions and chosen for
/// the least worst distance of the output y = Σ h_i x_(n−i) from the path (the line before, the
/// arc, the line after): iteratively reweighted least squares on the linearised distance,
/// `iterations` passes of which the best is kept, Tikhonov weight lambda in units of the steady
/// correction at the planned speed.
class ArcEndFit {
 public:
  static constexpr int kEndSamples = 6;

  ArcEndFit(std::vector<double> weights, double period_s, double lambda = 1e-3,
            int iterations = 40);

  ArcOffsets fit(const ArcRun& run) const;
  /// Today's interpolator: c blended in (out) linearly over the arc's first (last)
  /// min(L/2, 2·T·v_planned) of path, no tangential part.
  ArcOffsets linear_blend(const ArcRun& run) const;
  /// The worst distance of the output from the path, every sample whose window is full, over
  /// the steady loss r(1 − A) at the planned speed.
  double worst_fraction(const ArcRun& run, const ArcOffsets& offsets) const;
  /// A(x) = Σ h_i cos((i − m)·x).
  double gain(double x) const;

 private:
  struct Samples;  // the run's path positions, frames, steady corrections and filtered positions
  Samples prepare(const ArcRun& run) const;

  std::vector<double> h_;
  double period_s_;
  double centre_ = 0.0;
  double lambda_;
  int iterations_;
};

}  // namespace gm
