// Program-side positions: the nine RS274/NGC axes (X Y Z A B C U V W) whatever the machine has.
#pragma once

#include "common/axis.hpp"

#include <Eigen/Core>

#include <array>

namespace gm {

/// The nine program axes in LinuxCNC's order.
inline constexpr int kProgramAxes = kMaxAxes;
inline constexpr std::array<char, kProgramAxes> kProgramAxisLetters = kAxisLetters;

/// A position or offset on the nine program axes (unit in the variable name). The same vector
/// type as a canonical move's positions (AxisVec, program order).
using Pos9 = AxisVec;

/// Index of program axis `letter` (0..8), or -1.
constexpr int program_axis_index(char letter) {
  return axis_index(letter);
}

/// What a canonical move carries of a program-side position: the machine's axes (others 0).
inline AxisVec to_machine(const Pos9& p, const AxisLayout& l) {
  if (l.is_xyz()) return xyz(p[0], p[1], p[2]);
  AxisVec v = AxisVec::Zero();
  for (int a = 0; a < l.count; ++a) v[l.program(a)] = p[l.program(a)];
  return v;
}

}  // namespace gm
