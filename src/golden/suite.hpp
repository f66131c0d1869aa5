// A golden suite: a folder with suite.toml listing cases, or a folder of programs run with
// defaults.
#pragma once

#include "golden/trace_compare.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace gm::golden {

/// One case: what to run and what of its result is pinned.
struct GoldenCase {
  std::string name;     ///< unique in the suite; names the stored files
  std::string program;  ///< as written in the suite (relative to the root) — for messages
  std::filesystem::path program_path;
  std::string flags;    ///< `gmotion run` flags (machine, profile, τ, overrides, ...), one string
  std::string machine;  ///< key `machine` (= --machine), relative to the root; "" = none
  std::string override_file;  ///< key `override_file` (= --override-file); "" = none
  int decimate = 1;           ///< key `decimate` (= --decimate)
  PinSpec pins;
  bool pin_summary = true;  ///< the summary JSON must be byte-identical too
};

struct Suite {
  std::filesystem::path dir;    ///< the suite folder
  std::filesystem::path root;   ///< case paths are relative to it
  std::filesystem::path store;  ///< where the goldens are kept
  std::string name;             ///< for JUnit
  std::vector<GoldenCase> cases;
};

/// Reads `dir`/suite.toml, or lists `dir`'s programs (*.nc, *.ngc) when there is none. Throws
/// gm::InputError naming the file, line and key of a mistake.
Suite load_suite(const std::filesystem::path& dir);

}  // namespace gm::golden
