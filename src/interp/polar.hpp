// LinuxCNC's polar coordinates: `@` radius and `^` angle (degrees) in place of X and Y, about the
// origin of the current coordinate system in the XY plane.
#pragma once

#include "grammar/parse.hpp"

#include <string>

namespace gm {

/// The polar words of a block (null when absent).
struct PolarWords {
  const grammar::Word* radius = nullptr;  ///< `@`, program units
  const grammar::Word* angle = nullptr;   ///< `^`, degrees counter-clockwise from +X
  bool any() const { return radius != nullptr || angle != nullptr; }
  /// The first of the two written (for error locations).
  const grammar::Word* first() const {
    if (radius == nullptr) return angle;
    if (angle == nullptr) return radius;
    return radius->loc.column < angle->loc.column ? radius : angle;
  }
};

/// The XY end of a motion with polar words, as LinuxCNC's find_ends: `x`, `y` hold the current
/// point (program coordinates and units) and receive the end. Absolute (G90): `@` and `^` are
/// the end's radius and angle, a missing one taken from the current point. Incremental (G91):
/// `@` is added to the radius, then `^` to the angle. False with `why` when the direction is
/// indeterminate (the current point is the origin and no angle is given).
bool polar_end(const PolarWords& p, bool incremental, double& x, double& y, std::string& why);

/// A canned cycle's start in absolute mode (G90): the radius `@` (else the current point's) at
/// the angle `^` (else the current point's); no indeterminate case (rs274: atan2(0, 0) = 0).
void polar_cycle_start(const PolarWords& p, double& x, double& y);

/// One repeat of an incremental (G91) canned cycle: the hole (x, y) moves `dr` outwards, then
/// turns `dtheta_deg` about the origin. False with `why` at the origin.
bool polar_cycle_step(double dr, double dtheta_deg, double& x, double& y, std::string& why);

}  // namespace gm
