// A double as a JSON value for the CLI's JSON outputs: shortest round-trip text, null when not
// finite.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <string>

namespace gm::cli {

inline std::string json_number(double v) {
  return std::isfinite(v) ? fmt::format("{}", v) : "null";
}

}  // namespace gm::cli
