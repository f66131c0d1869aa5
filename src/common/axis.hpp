// Axis indexing and the fixed-capacity per-axis vectors every stage uses (never a field per axis).
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>

namespace gm {

/// Up to nine axes, X Y Z A B C U V W (LinuxCNC's order). A, B and C are rotary (degrees).
inline constexpr int kMaxAxes = 9;

enum class Axis : int { X = 0, Y = 1, Z = 2, A = 3, B = 4, C = 5, U = 6, V = 7, W = 8 };

/// Upper-case letters of the nine program axes, index = Axis.
inline constexpr std::array<char, kMaxAxes> kAxisLetters{'X', 'Y', 'Z', 'A', 'B',
                                                         'C', 'U', 'V', 'W'};

/// Per-axis real values on the nine program axes (index = Axis; absent axes 0), e.g. a position
/// on the path. The unit is in the variable name (`_mm`: mm for linear axes, degrees for A, B, C).
using AxisVec = Eigen::Matrix<double, kMaxAxes, 1>;
/// Per-machine-axis integer positions or increments in BLU (encoder counts), in the machine's
/// axis order (AxisLayout): entries 0..count-1 are used, the rest stay 0.
using AxisBlu = Eigen::Matrix<std::int64_t, kMaxAxes, 1>;
/// Per-machine-axis real values in the machine's axis order (entries past the count stay 0).
using MachineVec = Eigen::Matrix<double, kMaxAxes, 1>;

/// The per-sample path (interpolator output, Acc/Dec, servo, the record handed to the second
/// thread) is compiled once for each axis count 1..kMaxAxes and chosen once, when a run starts,
/// from the machine's count: inside it every per-axis loop has a compile-time trip count. This
/// list is the one place those counts are named (explicit instantiations expand it).
#define GM_FOR_EACH_AXIS_COUNT(X) X(1) X(2) X(3) X(4) X(5) X(6) X(7) X(8) X(9)

/// Calls f(std::integral_constant<int, N>{}) with N = `count` (1..kMaxAxes) and returns its
/// result: the one run-time dispatch to the per-sample code compiled for N axes.
template <typename F>
decltype(auto) with_axis_count(int count, F&& f) {
  switch (count) {
#define GM_AXIS_COUNT_CASE(N) \
  case N:                     \
    return f(std::integral_constant<int, N>{});
    GM_FOR_EACH_AXIS_COUNT(GM_AXIS_COUNT_CASE)
#undef GM_AXIS_COUNT_CASE
    default:
      return f(std::integral_constant<int, kMaxAxes>{});  // not reached: counts are 1..9
  }
}

/// Index (0..8) of axis `letter` (upper case), or -1.
constexpr int axis_index(char letter) {
  for (int i = 0; i < kMaxAxes; ++i)
    if (kAxisLetters[static_cast<std::size_t>(i)] == letter) return i;
  return -1;
}

/// A, B and C turn (degrees); X Y Z U V W are linear (mm).
constexpr bool axis_is_rotary(int axis) {
  return axis >= 3 && axis <= 5;
}

/// A position on X, Y and Z (the other axes 0).
inline AxisVec xyz(double x, double y, double z) {
  AxisVec v = AxisVec::Zero();
  v[0] = x;
  v[1] = y;
  v[2] = z;
  return v;
}
/// BLU on the first three machine axes (the rest 0).
inline AxisBlu blu3(std::int64_t x, std::int64_t y, std::int64_t z) {
  AxisBlu v = AxisBlu::Zero();
  v[0] = x;
  v[1] = y;
  v[2] = z;
  return v;
}

/// The axes a machine has, in its order (a subsequence of XYZABCUVW): machine axis i is program
/// axis `index[i]`. Plain data, copied into every stage that maps between the two orders.
struct AxisLayout {
  int count = 3;
  std::array<int, kMaxAxes> index{0, 1, 2, 0, 0, 0, 0, 0, 0};

  /// The layout of `letters` (upper or lower case, in XYZABCUVW order, no repeats, at least one),
  /// or nullopt.
  static std::optional<AxisLayout> of(std::string_view letters) {
    AxisLayout l;
    l.count = 0;
    int last = -1;
    for (const char c : letters) {
      const int i = axis_index(c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c);
      if (i < 0 || i <= last || l.count == kMaxAxes) return std::nullopt;
      l.index[static_cast<std::size_t>(l.count++)] = i;
      last = i;
    }
    if (l.count == 0) return std::nullopt;
    return l;
  }
  /// Upper-case letter of machine axis `a`.
  char letter(int a) const { return kAxisLetters[static_cast<std::size_t>(program(a))]; }
  /// Program axis (0..8) of machine axis `a`.
  int program(int a) const { return index[static_cast<std::size_t>(a)]; }
  /// "XYZ", "XYZA", ...
  std::string letters() const {
    std::string s;
    for (int a = 0; a < count; ++a) s += letter(a);
    return s;
  }
  /// True if the machine has program axis `axis` (0..8).
  bool has(int axis) const {
    for (int a = 0; a < count; ++a)
      if (program(a) == axis) return true;
    return false;
  }
  /// Exactly X, Y and Z.
  bool is_xyz() const { return count == 3 && index[0] == 0 && index[1] == 1 && index[2] == 2; }
};

}  // namespace gm
