// Residual vibration of an impulse sequence or of Acc/Dec taps for a mode (f, ζ), and robustness.
#pragma once

#include "accdec/shapers.hpp"

#include <vector>

namespace gm {

/// Percentage residual vibration (as a ratio) of impulses A_i at t_i for a second-order mode of
/// natural frequency f and damping ratio ζ (Singer & Seering 1990; Singhose):
///   V = e^(−ζω t_n) · |Σ A_i e^(ζω t_i) e^(jω_d t_i)| / Σ A_i,  ω = 2πf, ω_d = ω√(1−ζ²),
/// t_n the last impulse with A_i ≠ 0: the vibration left after the sequence relative to the
/// vibration a single impulse of the same area leaves (V = 1 unshaped, 0 = cancelled). Evaluated
/// as Σ A_i e^(−ζω(t_n − t_i)) so long sequences cannot overflow. For a convolution of two
/// sequences V is the product of theirs.
double residual_vibration(const ShaperImpulses& impulses, double freq_hz, double damping);

/// The same for taps h_i at times i·T (what the FIR applies).
double residual_vibration(const std::vector<double>& taps, double period_s, double freq_hz,
                          double damping);

/// A band of frequency, Hz.
struct FrequencyBand {
  double lo_hz = 0;
  double hi_hz = 0;
};

/// Robustness of taps against a mode near f: V at f and at f ± 20 %, and the bands within
/// [f/2, min(2f, 1/T)] where V ≤ `limit` (an EI shaper's V(f) is its tolerance, so its band can
/// be two, one either side of f).
struct VibrationRobustness {
  double v_at_f = 0;
  double v_minus_20 = 0;             ///< V(0.8 f)
  double v_plus_20 = 0;              ///< V(1.2 f)
  std::vector<FrequencyBand> bands;  ///< ascending; edges bisected to 1e-6 f
  /// The band holding f, or a zero-width band at f when none does.
  FrequencyBand band_at_f(double freq_hz) const;
};
/// Scans [f/2, min(2f, 1/T)] in steps of f/1000, then bisects each edge.
VibrationRobustness vibration_robustness(const std::vector<double>& taps, double period_s,
                                         double freq_hz, double damping, double limit = 0.05);

}  // namespace gm
