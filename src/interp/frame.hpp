// Program and machine coordinates, in LinuxCNC's order: machine = R(θ)·(program + G92) + G5x +
// tool offset, where R(θ) turns X and Y by the active coordinate system's rotation (G10 L2 R).
#pragma once

#include "interp/interpreter.hpp"

namespace gm {

/// Turns (x, y) counterclockwise by `deg` degrees (LinuxCNC's rotate()).
void rotate_xy(double& x, double& y, double deg);

/// Makes `cs` (0..8 = G54..G59.3) the active system with its offsets and rotation from `t`.
inline void select_coord_system(ModalState& s, const SystemTables& t, int cs) {
  s.coord_system = cs;
  s.g5x_mm = t.g5x_mm[static_cast<std::size_t>(cs)];
  s.g5x_rotation_deg = t.g5x_rotation_deg[static_cast<std::size_t>(cs)];
}

/// The coordinate transform of one state: the active system's offsets and rotation.
class Frame {
 public:
  explicit Frame(const ModalState& s) : s_(s), g5x_(s.g5x_mm), rotation_deg_(s.g5x_rotation_deg) {}

  /// True when the active system is rotated (the XY axes then mix).
  bool rotated() const { return rotation_deg_ != 0.0; }
  double rotation_deg() const { return rotation_deg_; }
  /// Sum of the offsets, mm (the whole transform when not rotated).
  Pos9 offset() const { return g5x_ + s_.g92_mm + s_.tool_offset_mm; }
  /// offset()[i], with the same additions on that axis alone.
  double offset(int i) const { return g5x_[i] + s_.g92_mm[i] + s_.tool_offset_mm[i]; }
  /// Program coordinates (mm, before units) of the machine point `m`.
  Pos9 to_program(const Pos9& m) const;
  /// `m` (machine, mm) with the program coordinates of the axes in `mask` (bit i = axis i) set to
  /// `p`'s (mm); the other axes stay exactly as they are.
  Pos9 to_machine(const Pos9& m, const Pos9& p, unsigned mask) const;
  /// A program-frame displacement (mm) as a machine displacement (G91 words, I J K).
  void turn(double& dx, double& dy) const {
    if (rotated()) rotate_xy(dx, dy, rotation_deg_);
  }

 private:
  const ModalState& s_;
  const Pos9& g5x_;
  double rotation_deg_;
};

}  // namespace gm
