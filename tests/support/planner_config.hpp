// The tolerance planner's settings for a machine's Acc/Dec output, as tests build them.
#pragma once

#include "machine/machine.hpp"
#include "planner/tolerance_planner.hpp"

namespace gmtest {

/// The planner for `m`'s FIR alone (no servo chain, so no truncation margin): its largest
/// override, rapid rate and BLU rounding, arcs pre-compensated when `precomp`.
inline gm::PlannerConfig fir_planner_config(const gm::Machine& m, bool precomp) {
  gm::PlannerConfig c;
  c.max_override = m.max_override;
  c.rapid_mm_min = m.rapid_mm_min;
  c.rounding_mm = m.xyz_blu_mm().norm();
  c.precompensate_arcs = precomp;
  c.precompensate_g61_arcs = m.g61_arc_precompensation;
  c.private_arcs = m.private_arcs;
  return c;
}

}  // namespace gmtest
