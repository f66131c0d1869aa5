// Axis indexing and the fixed-size per-axis vectors every stage uses (never a field per axis).
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>

namespace gm {

inline constexpr int kAxes = 3;

enum class Axis : int { X = 0, Y = 1, Z = 2 };

/// Per-axis real values; the unit is in the variable name (`_mm`, `_mm_s`, ...).
using AxisVec = Eigen::Matrix<double, kAxes, 1>;
/// Per-axis integer positions or increments in BLU (basic length units, encoder counts).
using AxisBlu = Eigen::Matrix<std::int64_t, kAxes, 1>;

/// Upper-case axis letters, index = Axis.
inline constexpr std::array<char, kAxes> kAxisLetters{'X', 'Y', 'Z'};

}  // namespace gm
