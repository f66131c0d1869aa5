// The pre-compensated arc's simulated term per unit radius, tabulated lazily over (ωT, sweep):
// an arc's bound from four table values instead of a simulation per bisected speed.
#pragma once

#include "planner/arc_precomp.hpp"

#include <cstddef>
#include <vector>

namespace gm {

/// ArcPrecompCheck::error_mm scales with the radius: the isolated arc, its blend (min(L/2,
/// 2·T·v_p) of path), the correction r(1/A(ωT) − 1) and the ramp are all lengths in units of r
/// once the sweep |θ| and the in-plane rate x = ωT = v_p·|θ|/L·T are fixed (a helix only adds
/// its axial line, which the filter passes with the delay). So error_mm = r·E(x, |θ|), and E
/// is tabulated once per filter: nodes on geometric grids in x and |θ|, each simulated by
/// error_mm(1, θ_j, θ_j, x_k/T) the first time a lookup needs it (a program pays only for the
/// cells its arcs reach).
///
/// Between nodes, E/x² is interpolated bilinearly in (log x, log |θ|) on the logarithm of the
/// node values and multiplied by (1 + kMargin). E/x² and the interpolation are smooth where the
/// table is used; what the margin must cover (the interpolation's error, the sampling phase's
/// wiggle) is measured against the simulation on random arcs in tests/planner
/// (test_arc_precomp.cpp, "the residual table bounds the simulation"). Arcs outside the table
/// (sweep below kMinSweep, rate below the grid, arcs shorter than kMinSamples samples of
/// travel) are not covered: the caller simulates them as before.
///
/// From |θ| > 4(N + 1)·x on (N + 1 weights) the check simulates the arc's two ends only and E no
/// longer depends on |θ|: sweeps beyond the grid's top, 4(N + 1)·limit, take its top column.
class ArcResidualTable {
 public:
  static constexpr double kMargin = 0.06;
  static constexpr double kStep = 1.06;         ///< ratio of neighbouring nodes, in x and |θ|
  static constexpr double kMinSweep = 0.01;     ///< rad
  static constexpr double kRateRange = 4096.0;  ///< the grid's x from limit/kRateRange
  static constexpr double kMinSamples = 0.5;    ///< the arc at least this many samples long

  /// `judging`: how the check judges the arcs of this table (ArcPrecompCheck::Judging), its
  /// nodes simulated so.
  explicit ArcResidualTable(const ArcPrecompCheck& check,
                            ArcPrecompCheck::Judging judging = ArcPrecompCheck::Judging::Shared);
  /// Whether error_bound_mm covers this arc at this speed.
  bool covers(double sweep_abs_rad, double length_mm, double v_plan) const;
  /// r·E(x, |θ|)·(1 + kMargin) by the table (covers() must hold), mm; `check` (the one the
  /// table was built for) simulates the nodes not yet filled.
  double error_bound_mm(const ArcPrecompCheck& check, double radius_mm, double sweep_abs_rad,
                        double length_mm, double v_plan) const;
  /// r·M(x)·(1 + kMargin) with M(x) = ramps_mm(1, 1, 1, x/T), a bound on
  /// ArcPrecompCheck::ramps_mm (the middle of an arc whose ends are slower): like the ramp, the
  /// ramps run on the steady arc, whose samples turn by x and whose correction is r·(1/A(x) − 1),
  /// so they depend on r and x only. One row of nodes in x, M/x² interpolated linearly in log x
  /// on its logarithm (covers() must hold), mm.
  double ramps_bound_mm(const ArcPrecompCheck& check, double radius_mm, double sweep_abs_rad,
                        double length_mm, double v_plan) const;
  /// Nodes simulated so far (the ramps' row included).
  std::size_t nodes_filled() const { return filled_; }

 private:
  /// log(E/x²) at node (x_k, θ_j), simulated by `check` the first time.
  double log_g(const ArcPrecompCheck& check, std::size_t k, std::size_t j) const;
  /// The ramp's transient at x_k per unit radius, simulated once per row: ramp_mm(1, θ, θ,
  /// x_k/T) is the same for every θ (q = θ/θ = 1, the rate x_k/T·θ/θ = x_k/T) but for the
  /// rounding of v·θ/θ; the row takes it at θ = 1, where that rounding is exact.
  double row_ramp(const ArcPrecompCheck& check, std::size_t k, double x) const;
  /// log(M/x²) at x_k, simulated by `check` the first time.
  double log_ramps(const ArcPrecompCheck& check, std::size_t k) const;
  /// The arc's in-plane rate x = ωT = v_p·|θ|/L·T.
  double rate(double sweep_abs_rad, double length_mm, double v_plan) const;
  /// The grid's position of rate x: fractional index, clamped to the grid.
  double rate_index(double x) const;
  double period_s_ = 0;
  ArcPrecompCheck::Judging judging_ = ArcPrecompCheck::Judging::Shared;
  double x0_ = 0, x_top_ = 0, th_top_ = 0, inv_log_step_ = 0;
  std::size_t nx_ = 0, nth_ = 0;
  mutable std::vector<double> log_g_;      ///< nx_·nth_, NaN until simulated
  mutable std::vector<double> ramp_;       ///< nx_, NaN until simulated
  mutable std::vector<double> log_ramps_;  ///< nx_: log(M/x²), NaN until simulated
  mutable std::size_t filled_ = 0;
};

}  // namespace gm
