// Arc geometry from the block's words: centre by IJK or R, and the per-controller tolerance rules.
#pragma once

#include "common/error_codes.hpp"
#include "machine/machine.hpp"

#include <string>

namespace gm {

/// An arc problem in the plane's two coordinates (a, b): LinuxCNC's order, XY for G17,
/// ZX for G18, YZ for G19. Lengths in program units (mm, or inch under G20) because the
/// LinuxCNC tolerances are defined per unit system; `mm_per_unit` converts for the others.
struct ArcInput {
  double start_a = 0, start_b = 0;
  double end_a = 0, end_b = 0;
  bool use_r = false;
  double r = 0;                 ///< R word (negative: the arc over 180 degrees)
  double off_a = 0, off_b = 0;  ///< I/J/K offsets in the plane (or absolute centre under G90.1)
  bool offsets_absolute = false;
  bool ccw = false;
  double mm_per_unit = 1.0;  ///< 1 (G21) or 25.4 (G20)
  ArcRule rule = ArcRule::LinuxCnc;
};

struct ArcResult {
  ErrorCode error = ErrorCode::None;
  std::string message;  ///< with the numbers involved when `error` is set
  double center_a = 0, center_b = 0;
  /// Centre minus start, computed without cancellation (exactly I/J/K for incremental offsets).
  double rel_a = 0, rel_b = 0;
};

/// Computes the centre; checks zero radius, R reach and the start/end radius mismatch with
/// `in.rule` (LinuxCNC: interp_arc.cc arc_data_ijk/arc_data_r; grbl: gcode.c; g2core:
/// plan_arc.cpp). Never throws.
ArcResult compute_arc(const ArcInput& in);

}  // namespace gm
