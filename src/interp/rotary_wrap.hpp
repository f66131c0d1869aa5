// Wrapped rotary axes (LinuxCNC's [AXIS_n]WRAPPED_ROTARY): positions modulo 360°, turned by sign.
#pragma once

#include "machine/machine.hpp"

#include <cmath>

namespace gm {

/// Whether program axis `program_axis` (0..8, XYZABCUVW) is a wrapped rotary axis of `m`.
inline bool axis_wraps(const Machine& m, int program_axis) {
  if (!axis_is_rotary(program_axis)) return false;
  for (int i = 0; i < m.layout.count; ++i)
    if (m.layout.program(i) == program_axis)
      return m.axes[static_cast<std::size_t>(i)].wrapped_rotary;
  return false;
}

/// An absolute word on a wrapped axis must name an angle within one turn: |value| < 360.
inline bool wrapped_word_ok(double value_deg) {
  return value_deg > -360.0 && value_deg < 360.0;
}

/// Where an absolute `commanded_deg` (|commanded| taken as the angle) takes a wrapped axis now at
/// `current_deg`, all in the program's coordinates: the angle in current's turn, then the next
/// turn up when `sign_deg` (the word as written) is positive or +0 and that lies behind, or down
/// when it is negative or -0 and that lies ahead. So A270 from 350 turns forward to 630, A-270
/// from 350 back to 270, and A0 from 720 stays at 720.
inline double unwrap_rotary_deg(double sign_deg, double commanded_deg, double current_deg) {
  const double turn = std::floor(current_deg / 360.0) * 360.0;
  double r = std::fabs(commanded_deg) + turn;
  const bool backwards = std::signbit(sign_deg);
  if (!backwards && r < current_deg) r += 360.0;
  if (backwards && r > current_deg) r -= 360.0;
  return r;
}

/// A wrapped axis's position as its parameters show it (G28.1/G30.1, probe results): 0 ≤ a < 360.
inline double wrap_360(double a_deg) {
  double a = std::fmod(a_deg, 360.0);
  if (a < 0.0) a += 360.0;
  return a;
}

}  // namespace gm
