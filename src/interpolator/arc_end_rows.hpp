// The rows of a pre-compensated arc's ends: its command's offset in two directions as a function
// of how many samples' advance a sample lies from the arc's end, fitted once per filter.
#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace gm {

/// One end of a compensated arc. A sample u advances from the arc's start or end (as
/// ArcCompensation counts them: arc_compensation.hpp) is commanded off the arc by radial(u)·c
/// outwards and along(u)·c along the motion (reversed at the end), c = r(1/A(x) − 1) its steady
/// correction at its in-plane advance x·r. radial and along are piecewise linear in u with
/// knots at u = 1 .. kSpan − 1, (0, 0) at u = 0 and the steady (1, 0) from u = kSpan on; the
/// knot values depend on x (linear between rate knots at fractions of the rule's limit,
/// clamped). Where both ends reach a sample their deviations from the steady offset add. Three
/// sets: Way::Moving for a start and an end the command moves on from, Way::Stopping for an
/// end where it stops on the end point, Way::MovingDistance for a moving end of a private arc.
///
/// The knot values are fitted (ArcEndFit::fit_shared) on endless arcs at constant rate for the
/// least worst |y − x(s̄)| of the Acc/Dec output (the measure the tolerance planner adds up over
/// a path's elements) with a small weight on their size, over kPhases phases of the join within
/// its sample at once, at constant speed and with the speed falling or rising at the ramp's
/// rate around the join (an end reached while the speed ramps, seen backwards in time: the
/// filter is symmetric, or these are the rows of a filter's reversed weights, which
/// ArcCompensation uses at the ends): Moving on a line into the arc, and from rest with the
/// interpolator's ramp;
/// Stopping with the command held on the join, which is a stop seen backwards. Each leaves
/// about 9–13 % of the steady loss r(1 − A) where the radial blend leaves 16–29 %
/// (docs/tolerance-arc-ends.md, "End rows"). MovingDistance: Moving's runs and the speed ramped
/// through positions on the line before the join, fitted for the least worst distance from the
/// path (the output may run ahead of or behind s̄): 5–6.5 % of the loss by the distance, where
/// Moving's leave 9–12 % (docs/tolerance-arc-ends.md, "Private arcs"); fitted only once a
/// private arc asks for one.
class ArcEndRows {
 public:
  static constexpr int kSpan = 4;
  static constexpr int kPhases = 8;
  static constexpr double kMu = 1e-4;  ///< the fit's weight on the offsets' size (fit_shared)
  /// The longest window fitted (weights): Moving's and Stopping's twelve sets take about 75 ms
  /// of CPU at 41, 350 ms at 128, MovingDistance's six (for private arcs) about 0.18 and 0.7 s
  /// more (Blackman, 2026-12-02), growing with the window; longer filters keep the radial blend
  /// (ArcCompensation::rows_weight).
  static constexpr std::size_t kMaxWindow = 128;
  static constexpr std::array<double, 6> kRateKnots{0.02, 0.1, 0.3, 0.55, 0.8, 1.0};  ///< × limit

  /// Factors of c, radial and along.
  struct Shape {
    double radial = 1.0, along = 0.0;
  };
  /// MovingDistance: Moving's runs, fitted for the least worst distance from the path instead
  /// (the output may run ahead of or behind s̄ near the join); its along knots are read
  /// linearly in along·x between the rate knots (they go about as 1/x).
  enum class Way { Moving, Stopping, MovingDistance };
  static constexpr std::size_t kWays = 3;

  ArcEndRows() = default;  ///< empty: the steady offset everywhere
  ArcEndRows(const ArcEndRows&) = delete;
  ArcEndRows& operator=(const ArcEndRows&) = delete;
  /// Stops the background fits after the set in hand and waits for it.
  ~ArcEndRows();
  /// The rows of the filter's weights (Σ = 1) at period T, rates up to `limit_x`
  /// (ArcCompensation::limit_omega_t()). Each rate knot's set of each way is fitted when at()
  /// first needs it (a program's arcs use a few of them; the fits are the rows' whole cost).
  ArcEndRows(const std::vector<double>& weights, double period_s, double limit_x);

  /// The rows of this filter, fitted on the first request and kept for the process (the last
  /// few filters asked for): an interpolator and a planner of one machine share them. The
  /// first set asked for starts a thread that fits the others in turn meanwhile (a program
  /// with arcs soon asks for most of them: the planner's residual table sweeps the rates);
  /// a set asked for while that thread fits it is waited for, one it has not reached is
  /// fitted by the caller. The knots are the same whichever thread fits them.
  static std::shared_ptr<const ArcEndRows> shared(const std::vector<double>& weights,
                                                  double period_s, double limit_x);

  bool empty() const { return !enabled_; }
  /// The end's shape at u advances from it (u < kSpan) at rate x.
  Shape at(double u, double x, Way way) const;
  /// max over u = 1 .. kSpan − 1 of |radial − 1| + |along| of at(u, x, way), bit for bit, with
  /// one lookup of the rate's knots (at whole u the shape is its inner knot's).
  double largest_deviation(double x, Way way) const;

 private:
  static constexpr int kInner = kSpan - 1;  ///< knots u = 1 .. kSpan − 1
  /// The fixed part at u and the weights of the inner knots (hat functions).
  static void basis(double u, double& fixed, std::array<double, kInner>& hat);
  /// One rate knot's set of one way: radial at the inner knots, then along (in units of c).
  using Knots = std::array<double, 2 * kInner>;
  /// The sets of the rate knots below and above rate x (clamped) and x's place between them.
  struct RateKnots {
    const Knots *lo, *hi;
    double f;
    double x_lo, x_hi;  ///< the two knots' rates
  };
  RateKnots rate_knots(double x, Way way) const;
  /// The along knot i (kInner..) of `way` between k's rate knots.
  static double along_at(const RateKnots& k, std::size_t i, Way way);
  /// The set of rate knot `rate` and `way`, fitted on the first request (thread-safe).
  const Knots& knots(std::size_t rate, Way way) const;
  Knots fit(std::size_t rate, Way way) const;  ///< that set's fit
  /// Fits the set if no thread has begun it (true), else returns false at once.
  bool claim_and_fit(std::size_t rate, std::size_t way) const;
  void fit_the_rest() const;  ///< the background thread: every set not begun, until stopped
  std::vector<double> weights_;
  double period_s_ = 0.0, limit_x_ = 0.0;
  bool enabled_ = false;
  enum State : int { kNotBegun, kFitting, kDone };
  struct Lazy {
    std::atomic<int> state{kNotBegun};
    Knots k{};  ///< written before state becomes kDone (release), read after (acquire)
  };
  mutable std::array<std::array<Lazy, kWays>, kRateKnots.size()> lazy_;  ///< [rate][way]
  mutable std::mutex done_lock_;
  mutable std::condition_variable done_;  ///< a set became kDone
  mutable std::once_flag rest_started_;
  mutable std::atomic<bool> stop_{false};
  mutable std::atomic<bool> distance_wanted_{false};  ///< a MovingDistance set was asked for
  mutable std::thread rest_;                          ///< fit_the_rest, joined by the destructor
};

}  // namespace gm
