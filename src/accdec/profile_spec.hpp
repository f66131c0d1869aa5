// Parsing of an Acc/Dec profile spec string ("blackman", "kaiser:6@max", "custom:0.5,1,2,1,0.5",
// ...).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace gm {

/// The profile families of the paper (sections 2, 4, 5) plus a few window and cascade variants.
enum class ProfileKind {
  Linear,   ///< b_i = 1 (moving average, Eq. 15)
  SCurve1,  ///< s(t) = 3t^2 - 2t^3 mapped by Eq. 20/22a/23
  SCurve2,  ///< s(t) = 10t^3 - 15t^4 + 6t^5 mapped by Eq. 21/22b/23
  Window,   ///< windowed ideal low-pass (Matlab fir1), section 5 step 2
  Custom,   ///< user taps b_0..b_N (e.g. the paper's Fig. 5d: 0.5,1,2,1,0.5)
  Cascade   ///< convolution of moving averages of lengths L1, L2, ...
};

/// Window used by ProfileKind::Window (symmetric, N+1 points, as Matlab
/// blackman/hann/hamming/kaiser).
enum class WindowKind { Blackman, Hann, Hamming, Kaiser };

/// How the cutoff of a window design is chosen.
enum class CutoffRule {
  Paper,      ///< Eq. 25: w = 2/(N+1) (the default)
  MaxNonNeg,  ///< "@max": the largest cutoff that keeps every tap >= 0 (closed form, see taps.cpp)
  Explicit    ///< "@0.05": the given value, normalised to Nyquist, in (0, 1]
};

/// Most moving averages a cascade profile may chain (each at most kMaxAccDecTaps long).
inline constexpr int kMaxCascadeStages = 16;

/// A parsed profile spec; only the members of its kind are meaningful.
struct ProfileSpec {
  std::string text;  ///< the spec as given
  ProfileKind kind = ProfileKind::Linear;
  WindowKind window = WindowKind::Blackman;
  double kaiser_beta = 0.0;
  CutoffRule cutoff_rule = CutoffRule::Paper;
  double cutoff = 0.0;               ///< for CutoffRule::Explicit
  std::vector<double> custom_taps;   ///< for Custom (raw, not normalised)
  std::vector<int> cascade_lengths;  ///< for Cascade (each >= 1)

  /// Number of taps fixed by the spec itself (Custom, Cascade), else 0 (taps follow tau/T).
  int fixed_length() const;
};

/// Parses `spec`:
///   linear | scurve1 | scurve2 | blackman[@C] | hann[@C] | hamming[@C] | kaiser:BETA[@C]
///   | custom:b0,b1,... | cascade:L1,L2,...        where C = a cutoff in (0,1] or "max".
/// Throws gm::InputError naming the bad part and listing the accepted forms.
ProfileSpec parse_profile_spec(std::string_view spec);

}  // namespace gm
