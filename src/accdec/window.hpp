// Symmetric window functions of M points (as Matlab blackman/hann/hamming/kaiser) and the fir1
// design.
#pragma once

#include <vector>

namespace gm {

/// Window functions of the window designs (symmetric, N+1 points, as Matlab
/// blackman/hann/hamming/kaiser).
enum class WindowKind { Blackman, Hann, Hamming, Kaiser };

/// The symmetric window w[0..M-1] (M >= 1; M == 1 gives {1}):
///  blackman 0.42 - 0.5cos(2πn/(M-1)) + 0.08cos(4πn/(M-1)), hann 0.5 - 0.5cos(2πn/(M-1)),
///  hamming 0.54 - 0.46cos(2πn/(M-1)), kaiser I0(β√(1-(2n/(M-1)-1)²))/I0(β).
/// Blackman and Hann are exactly zero at both ends (values within 1e-15 of 0 are set to 0).
std::vector<double> make_window(WindowKind kind, int points, double kaiser_beta = 0.0);

/// Matlab fir1(N, cutoff, window) for a low-pass: h[n] = c·sinc(c(n - N/2))·w[n], n = 0..N,
/// sinc(x) = sin(πx)/(πx), then scaled to DC gain 1 (sum = 1). `cutoff` normalised to Nyquist.
/// Taps whose magnitude is below 1e-12 of the largest are set to 0 (floating-point residue of
/// a window zero, e.g. Blackman's ends come out as -2e-20).
std::vector<double> fir1_lowpass(int order_N, double cutoff, const std::vector<double>& window);

/// The largest cutoff (normalised to Nyquist) keeping every fir1 tap >= 0 for this window:
/// the sinc's first zero must not fall inside the outermost non-zero window sample, i.e.
/// 2/N for windows non-zero at the ends (hamming, kaiser) and 2/(N-2) for windows zero at the
/// ends (blackman, hann; N > 2). Beyond it the tap at that sample goes negative.
double max_nonnegative_cutoff(WindowKind kind, int order_N);

/// Modified Bessel function of the first kind, order 0 (power series; for the Kaiser window).
double bessel_i0(double x);

}  // namespace gm
