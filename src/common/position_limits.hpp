// The range every position must stay in so that its count in BLU fits the integer stages.
#pragma once

namespace gm {

/// No program position (offsets included) may lie beyond ±kMaxPositionMm (interp checks it).
inline constexpr double kMaxPositionMm = 1e12;
/// The finest basic length unit a machine may have: 1 nm (0.001 µm, Fanuc's IS-E). With it a
/// position of ±kMaxPositionMm counts ±1e18 BLU, so a position minus another (the FIR's
/// relative positions) stays below 2^61 and every BLU sum the stages form fits int64.
inline constexpr double kMinBluMm = 1e-6;
static_assert(kMaxPositionMm / kMinBluMm <= 1.152921504606846976e18, "within 2^60 BLU");

}  // namespace gm
