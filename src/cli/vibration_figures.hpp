// Residual vibration, robustness and smoothing of one designed profile against a mode (f, ζ).
#pragma once

#include "accdec/taps.hpp"
#include "accdec/vibration.hpp"

#include <string>

namespace gm::cli {

/// What `analyze vibration` and `design --mode` print for a profile at tau and T.
struct VibrationFigures {
  Taps taps;
  double tau_s = 0;
  VibrationRobustness robustness;  ///< of the applied (integer) taps
  double v_continuous = 0;     ///< the spec's shapers as continuous impulses at f (NaN: no shaper)
  double sigma_s = 0;          ///< σ of the taps (FilterMoments::variance_s2)
  double corner_moment_s = 0;  ///< D(0)
  double corner_error_mm = 0;  ///< a 90° corner at the feed, no pause: V·D(0)
};

VibrationFigures vibration_figures(const std::string& profile, double tau_s, double period_s,
                                   double freq_hz, double damping, double feed_mm_min,
                                   double limit);

}  // namespace gm::cli
