// Program-side positions: the nine RS274/NGC axes (X Y Z A B C U V W) whatever the machine has.
#pragma once

#include "common/axis.hpp"

#include <Eigen/Core>

#include <array>

namespace gm {

/// The nine program axes in LinuxCNC's order.
inline constexpr int kProgramAxes = 9;
inline constexpr std::array<char, kProgramAxes> kProgramAxisLetters{'X', 'Y', 'Z', 'A', 'B',
                                                                    'C', 'U', 'V', 'W'};

/// A position or offset on the nine program axes (unit in the variable name).
using Pos9 = Eigen::Matrix<double, kProgramAxes, 1>;

/// Index of program axis `letter` (0..8), or -1.
constexpr int program_axis_index(char letter) {
  for (int i = 0; i < kProgramAxes; ++i)
    if (kProgramAxisLetters[static_cast<std::size_t>(i)] == letter) return i;
  return -1;
}

/// Program-axis index of each machine axis (the machine's AxisVec order).
inline constexpr std::array<int, kAxes> kMachineAxisIndex = [] {
  std::array<int, kAxes> idx{};
  for (int i = 0; i < kAxes; ++i)
    idx[static_cast<std::size_t>(i)] =
        program_axis_index(kAxisLetters[static_cast<std::size_t>(i)]);
  return idx;
}();

/// The machine's axes of a program-side position.
inline AxisVec to_machine(const Pos9& p) {
  AxisVec v;
  for (int i = 0; i < kAxes; ++i) v[i] = p[kMachineAxisIndex[static_cast<std::size_t>(i)]];
  return v;
}

/// A machine position widened to the nine program axes (absent axes 0).
inline Pos9 from_machine(const AxisVec& v) {
  Pos9 p = Pos9::Zero();
  for (int i = 0; i < kAxes; ++i) p[kMachineAxisIndex[static_cast<std::size_t>(i)]] = v[i];
  return p;
}

/// True if the machine has program axis `i` (0..8).
constexpr bool machine_has_axis(int i) {
  for (const int m : kMachineAxisIndex)
    if (m == i) return true;
  return false;
}

}  // namespace gm
