// The picture of a failed golden: both paths around the first divergence, the difference vs time.
#pragma once

#include "golden/trace_compare.hpp"

#include <filesystem>
#include <string>

namespace gm::golden {

/// Draws `png` from the golden and fresh traces (any readable trace files): on top both paths in
/// the plane of two axis columns around divergence `d` (golden blue, now red, the divergence
/// marked), below the difference now − golden of d's column against time. Returns "" or why not.
std::string draw_divergence(const std::string& golden_trace, const std::string& fresh_trace,
                            const Divergence& d, const std::string& title,
                            const std::filesystem::path& png);

}  // namespace gm::golden
