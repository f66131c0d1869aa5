// Program and machine coordinates under offsets and the XY rotation (LinuxCNC's find_relative /
// rotate_and_offset_pos order).
#include "interp/frame.hpp"

#include <cmath>
#include <numbers>

namespace gm {

void rotate_xy(double& x, double& y, double deg) {
  const double t = deg * std::numbers::pi / 180.0;
  const double c = std::cos(t), s = std::sin(t);
  const double xx = x * c - y * s;
  const double yy = x * s + y * c;
  x = xx;
  y = yy;
}

Pos9 Frame::to_program(const Pos9& m) const {
  Pos9 p = m - offset();
  if (rotated()) {
    double x = m[0] - g5x_[0] - s_.tool_offset_mm[0];
    double y = m[1] - g5x_[1] - s_.tool_offset_mm[1];
    rotate_xy(x, y, -rotation_deg_);
    p[0] = x - s_.g92_mm[0];
    p[1] = y - s_.g92_mm[1];
  }
  return p;
}

Pos9 Frame::to_machine(const Pos9& m, const Pos9& p, unsigned mask) const {
  Pos9 out = m;
  const Pos9 off = offset();
  for (int i = 0; i < kProgramAxes; ++i)
    if (mask & (1u << i)) out[i] = p[i] + off[i];
  if (rotated() && (mask & 3u)) {
    Pos9 q = to_program(m);
    if (mask & 1u) q[0] = p[0];
    if (mask & 2u) q[1] = p[1];
    double x = q[0] + s_.g92_mm[0], y = q[1] + s_.g92_mm[1];
    rotate_xy(x, y, rotation_deg_);
    out[0] = x + g5x_[0] + s_.tool_offset_mm[0];
    out[1] = y + g5x_[1] + s_.tool_offset_mm[1];
  }
  return out;
}

}  // namespace gm
