// Runs one golden case through the library's Run (no subprocess): binary trace, summary, set-up.
#pragma once

#include "golden/suite.hpp"

#include <cstdint>
#include <string>

namespace gm::golden {

/// What one run of a case produced.
struct CaseOutput {
  bool complete = false;  ///< the program ran to its end and the axes settled
  std::string error;      ///< why not (a program error, a stop rule, unsettled axes, bad flags)
  std::string summary_json;
  /// The machine as run (every key, flags applied) and the run's flags, as text: what the set-up
  /// hash covers. The program and the override schedule are not in it: a change there is a
  /// divergence to find, not a different set-up.
  std::string setup;
  std::uint64_t setup_hash = 0;
};

/// Runs case `c` of suite `s`, writing its binary trace to `trace_path`: its flags are the run
/// settings of `gmotion run` (setup::setting_rows()); the parameter file is read, never written.
/// Never throws: a failure is reported in CaseOutput::error.
CaseOutput run_case(const Suite& s, const GoldenCase& c, const std::string& trace_path);

/// FNV-1a, 64 bits (the set-up hash; stable across machines and versions).
std::uint64_t fnv1a64(std::string_view text);

}  // namespace gm::golden
