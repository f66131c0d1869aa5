// τ from acceleration limits: the shortest Acc/Dec filter through which a velocity step at each
// axis's speed limit stays within the axis's acceleration limit (docs/linuxcnc-ini.md).
#pragma once

#include <string>
#include <vector>

namespace gm {

/// Peak-to-mean ratio of the profile's taps, (N+1)·max h_k at N+1 = 1000 taps: a velocity step
/// V through the filter accelerates at most c·V/τ. 1 for linear; fixed-length profiles give 1.
double profile_peak_factor(const std::string& profile);

/// The smallest τ (a whole number of periods T, 1..kMaxAccDecTaps of them) at which a velocity
/// step at each axis's v_max_mm_s[i] through `profile` stays within a_max_mm_s2[i] (mm/s² or
/// deg/s²): ⌈c·max_i(V_i/A_i)/T⌉·T. Axes with A_i = 0 are skipped; `fallback_s` when none has a
/// limit.
double tau_for_accel_limit(const std::string& profile, double period_s,
                           const std::vector<double>& v_max_mm_s,
                           const std::vector<double>& a_max_mm_s2, double fallback_s);

}  // namespace gm
