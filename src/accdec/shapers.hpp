// Input shapers (ZV, ZVD, ZVDD, MZV, EI, 2-hump EI, 3-hump EI): impulse sequences and their taps.
#pragma once

#include <string_view>
#include <vector>

namespace gm {

/// The input shapers of the literature (Singer & Seering 1990; Singhose et al. 1994, 1997), with
/// the impulse sequences Klipper uses (klippy/extras/shaper_defs.py); ZVDD is ZV cubed.
enum class ShaperKind { ZV, ZVD, ZVDD, MZV, EI, TwoHumpEI, ThreeHumpEI };

/// Vibration tolerance the EI shapers are designed for (5 %: V(f) = 5 % at the design frequency).
inline constexpr double kEiVibrationTolerance = 0.05;

/// Damping ratio of a shaper spec without "@Z" (Klipper's default).
inline constexpr double kDefaultShaperDamping = 0.1;

/// Largest damping ratio a shaper's design holds for (the fits' range, as Klipper limits them).
constexpr double shaper_max_damping(ShaperKind kind) {
  return kind == ShaperKind::EI            ? 0.4
         : kind == ShaperKind::TwoHumpEI   ? 0.3
         : kind == ShaperKind::ThreeHumpEI ? 0.2
                                           : 0.99;
}

/// An impulse sequence: amplitudes (sum 1) at times (s, ascending, the first 0).
struct ShaperImpulses {
  std::vector<double> amplitude;
  std::vector<double> time_s;
  double duration_s() const { return time_s.empty() ? 0.0 : time_s.back(); }
};

/// The impulses of `kind` designed for a mode of natural frequency `freq_hz` (> 0) and damping
/// ratio `damping` in [0, 1). t_d = 1/(f·√(1−ζ²)) is the damped period; with
/// K = exp(−ζπ/√(1−ζ²)):
///   ZV   [1, K] at [0, t_d/2]
///   ZVD  [1, 2K, K²] at [0, t_d/2, t_d]
///   ZVDD [1, 3K, 3K², K³] at [0, t_d/2, t_d, 3t_d/2]
///   MZV  [1−1/√2, (√2−1)K', (1−1/√2)K'²] at [0, 3t_d/8, 3t_d/4], K' = K^(3/4)
///   EI, 2-hump EI, 3-hump EI: Singhose's curve fits in ζ for a 5 % vibration tolerance (3, 4 and
///   5 impulses over t_d, 1.5/f and 2/f).
/// Amplitudes are normalised to sum 1.
ShaperImpulses shaper_impulses(ShaperKind kind, double freq_hz, double damping);

/// Taps at period T for the impulses: an impulse at t = (k + p)T, 0 ≤ p < 1, puts (1 − p) of its
/// amplitude on tap k and p on tap k + 1 (linear interpolation between the two neighbouring
/// samples). Σ taps = 1.
std::vector<double> shaper_taps(const ShaperImpulses& impulses, double period_s);

/// Number of taps shaper_taps gives (the last impulse's sample, plus one when it falls between
/// samples); capped at `cap` (so absurd frequencies cannot overflow the count).
int shaper_tap_count(const ShaperImpulses& impulses, double period_s, int cap);

}  // namespace gm
