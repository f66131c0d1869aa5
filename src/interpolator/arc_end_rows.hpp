// A pre-compensated arc's ends in two directions: offsets on the arc's first samples, radial and
// tangential, that leave the Acc/Dec output nearest the path (docs/tolerance.md, "The arc's ends
// in two directions, judged by the distance to the path").
#pragma once

#include <array>
#include <vector>

namespace gm {

/// The command on the arc's first kSamples samples (the exit: the same, mirrored), for each
/// sample j after the join: radial[j] in units of the sample's own steady correction c (1 is the
/// steady correction, today's blend is (j + phase)/2), tangential[j] along the motion in units of
/// c/x, x the sample's advance over the radius. These units make the rows of a constant speed
/// nearly independent of x at small x.
struct ArcEndRows {
  static constexpr int kSamples = 6;
  std::array<double, kSamples> radial{};
  std::array<double, kSamples> tangential{};
};

/// The speeds around an entry, in the model's units (radius 1): x[i] is sample i's advance, the
/// samples running from the line before the arc onto the arc; sample `join` is the arc's first
/// and lies `phase` (0..1] of its advance past the arc's start.
struct ArcEndSpeeds {
  std::vector<double> x;
  int join = 0;
  double phase = 0.25;

  /// A constant rate x: two windows of line, then four windows of arc (`window` samples each).
  static ArcEndSpeeds constant(double x, double phase, int window);
};

/// Fits and measures ArcEndRows for a symmetric FIR (weights h_i, Σ = 1) on a line running into
/// an arc of radius 1 (the rows scale with the radius through c and x). The fit is the least
/// worst distance of the output y = Σ h_i x_(n−i) from the path (the line before and the
/// circle), by iteratively reweighted least squares on the linearised distance with a Tikhonov
/// weight lambda in units of the steady correction at the arc's rate; `iterations` passes.
class ArcEndFit {
 public:
  explicit ArcEndFit(std::vector<double> weights, double lambda = 1e-3, int iterations = 40);

  ArcEndRows fit(const ArcEndSpeeds& speeds) const;
  /// The worst distance of the output from the path over the whole run (every sample whose
  /// window is full), divided by the steady loss 1 − A(x) at the arc's rate (the largest x on the
  /// arc).
  double worst_fraction(const ArcEndSpeeds& speeds, const ArcEndRows& rows) const;
  /// Today's rule as rows: radial (j + phase)/2 up to 1, no tangential part.
  static ArcEndRows linear_blend(double phase);
  /// A(x) = Σ h_i cos((i − m)·x).
  double gain(double x) const;

 private:
  struct Run;  // the samples' positions, the command's base and the output's base
  Run prepare(const ArcEndSpeeds& speeds) const;

  std::vector<double> h_;
  double centre_ = 0.0;
  double lambda_;
  int iterations_;
};

}  // namespace gm
