// Polar coordinates (`@` radius, `^` angle): the end points LinuxCNC's find_ends and its canned
// cycles compute from them.
#include "interp/polar.hpp"

#include <cmath>
#include <numbers>

namespace gm {

namespace {

double radians(double degrees) {
  return degrees * std::numbers::pi / 180.0;  // as LinuxCNC D2R
}

void from_polar(double radius, double theta, double& x, double& y) {
  x = radius * std::cos(theta);
  y = radius * std::sin(theta);
}

}  // namespace

bool polar_end(const PolarWords& p, bool incremental, double& x, double& y, std::string& why) {
  if (!incremental) {
    if (p.radius != nullptr && p.angle != nullptr) {
      from_polar(p.radius->value, radians(p.angle->value), x, y);
    } else if (p.radius != nullptr) {
      if (x == 0.0 && y == 0.0) {
        why = "polar radius @ without an angle ^ at the origin: the direction is indeterminate";
        return false;
      }
      from_polar(p.radius->value, std::atan2(y, x), x, y);
    } else if (p.angle != nullptr) {
      from_polar(std::hypot(y, x), radians(p.angle->value), x, y);
    }
    return true;
  }
  if (p.radius != nullptr) {
    if (x == 0.0 && y == 0.0) {
      why = "incremental polar motion (G91 @) at the origin is indeterminate";
      return false;
    }
    from_polar(std::hypot(y, x) + p.radius->value, std::atan2(y, x), x, y);
  }
  if (p.angle != nullptr) {
    if (x == 0.0 && y == 0.0) {
      why = "incremental polar motion (G91 ^) at the origin is indeterminate";
      return false;
    }
    from_polar(std::hypot(y, x), std::atan2(y, x) + radians(p.angle->value), x, y);
  }
  return true;
}

void polar_cycle_start(const PolarWords& p, double& x, double& y) {
  const double radius = p.radius != nullptr ? p.radius->value : std::hypot(y, x);
  const double theta = p.angle != nullptr ? radians(p.angle->value) : std::atan2(y, x);
  from_polar(radius, theta, x, y);
}

bool polar_cycle_step(double dr, double dtheta_deg, double& x, double& y, std::string& why) {
  for (int k = 0; k < 2; ++k) {
    const double d = k == 0 ? dr : dtheta_deg;
    if (d == 0.0) continue;
    if (x == 0.0 && y == 0.0) {
      why = "incremental polar motion in a canned cycle at the origin is indeterminate";
      return false;
    }
    if (k == 0)
      from_polar(std::hypot(y, x) + dr, std::atan2(y, x), x, y);
    else
      from_polar(std::hypot(y, x), std::atan2(y, x) + radians(dtheta_deg), x, y);
  }
  return true;
}

}  // namespace gm
