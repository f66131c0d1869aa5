// Unit conversions, done once at the boundaries: inside, lengths are mm, times s, positions BLU.
#pragma once

namespace gm::units {

inline constexpr double kMmPerInch = 25.4;
inline constexpr double kSecondsPerMinute = 60.0;

/// mm/min -> mm/s.
constexpr double mm_min_to_mm_s(double v_mm_min) {
  return v_mm_min / kSecondsPerMinute;
}
/// mm/s -> mm/min.
constexpr double mm_s_to_mm_min(double v_mm_s) {
  return v_mm_s * kSecondsPerMinute;
}

inline constexpr double kMmPerMetre = 1000.0;
inline constexpr double kDegPerRadian = 57.295779513082320876798154814105;  // 180/π

/// An axis's unit (mm, or degrees on a rotary axis) per SI unit (metre, radian): what its
/// positions, speeds and accelerations are divided by before mass/inertia and damping act.
constexpr double unit_per_si(bool rotary) {
  return rotary ? kDegPerRadian : kMmPerMetre;
}

}  // namespace gm::units
